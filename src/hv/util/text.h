// Small text helpers the line-oriented readers share (control points, trajectories): one field of
// a CSV line, ASCII lower case, and a bounded, printable echo of bad input for messages.
#pragma once

#include <string>
#include <string_view>

namespace hv {

// Spaces, tabs and a carriage return removed from both ends, then one pair of double quotes.
std::string_view trimField(std::string_view s);
// ASCII letters in lower case, other bytes as they are.
std::string asciiLower(std::string_view s);
// The first 40 bytes, non-printable ones as '?', "..." when cut: safe to put in a message.
std::string shownText(std::string_view s);

}  // namespace hv
