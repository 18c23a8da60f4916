#include "hv/ibr/consensus.h"

#include <gtest/gtest.h>

#include <vector>

namespace hv::ibr {
namespace {

// Expected values from an independent implementation of the rule in consensus.h (median start,
// three mean-shift steps, kernel relative to the nearest sample), written in Python.
TEST(Consensus, ReweightsByTheKernelAroundTheMode) {
  std::vector<glm::dvec3> c = {{0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, {0.6, 0.5, 0.5}};
  std::vector<double> w = {1, 1, 1};
  consensusWeights(c, w, 0.1);
  EXPECT_NEAR(w[0], 1.0, 1e-12);
  EXPECT_NEAR(w[1], 1.0, 1e-12);
  EXPECT_NEAR(w[2], 0.8071064688560774, 1e-12);
}

TEST(Consensus, TheMajorityWinsWhateverTheWeights) {
  // A car in the most weighted photograph (weight 4) against three that show the empty street.
  std::vector<glm::dvec3> c = {{0.4, 0.3, 0.2}, {0.45, 0.35, 0.2}, {0.5, 0.3, 0.25}, {0.9, 0.8, 0.1}};
  std::vector<double> w = {1, 2, 1, 4};
  consensusWeights(c, w, 0.1);
  EXPECT_NEAR(w[0], 0.8769774214742406, 1e-12);
  EXPECT_NEAR(w[1], 2.0, 1e-12);
  EXPECT_NEAR(w[2], 0.8107641437206691, 1e-12);
  EXPECT_NEAR(w[3], 1.1982696364754375e-09, 1e-15);
}

TEST(Consensus, LeavesFewSamplesZeroWeightsAndSpreadZeroAlone) {
  std::vector<glm::dvec3> c = {{0.1, 0.1, 0.1}, {0.9, 0.9, 0.9}, {0.5, 0.5, 0.5}};
  std::vector<double> w = {1, 3, 0};  // two contribute: no majority
  consensusWeights(c, w, 0.1);
  EXPECT_EQ(w, (std::vector<double>{1, 3, 0}));
  w = {1, 3, 2};
  consensusWeights(c, w, 0.0);
  EXPECT_EQ(w, (std::vector<double>{1, 3, 2}));
  // Samples past kMaxConsensusSamples are not looked at (the shader keeps the first ones).
  std::vector<glm::dvec3> many(kMaxConsensusSamples + 2, glm::dvec3(0.5));
  many.back() = glm::dvec3(0.0);
  std::vector<double> wm(many.size(), 1.0);
  consensusWeights(many, wm, 0.05);
  EXPECT_EQ(wm.back(), 1.0);
  EXPECT_EQ(wm.front(), 1.0);
}

}  // namespace
}  // namespace hv::ibr
