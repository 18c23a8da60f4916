// Typed programs: a program's uniforms and samplers are resolved once, when it is linked, into
// named members of a C++ type, so no pass looks a uniform up by string while it draws. A name the
// linked program does not have is an error (thrown, naming the program and the uniform) unless the
// type declares it optional: a misspelt uniform fails at start-up instead of being set nowhere.
#pragma once

#include "hv/gpu/gl.h"

#include <stdexcept>
#include <string>

namespace hv::gpu {

// A type and its program disagree: a programming error, not a context that cannot link (callers
// that try program variants until one links catch std::runtime_error and must not catch this).
class MissingUniform : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

class UniformResolver {
 public:
  // `name`: the program as messages name it (its shader files and defines).
  UniformResolver(const Program& program, std::string name) : program_(program), name_(std::move(name)) {}

  // The location of `uniform`; throws MissingUniform when the linked program has no such
  // active uniform (an array is named by its first element or its bare name).
  GLint required(const char* uniform) const {
    const GLint loc = glGetUniformLocation(program_.id(), uniform);
    if (loc < 0)
      throw MissingUniform("program " + name_ + ": uniform '" + uniform +
                               "' is not an active uniform of the linked program (misspelt, or optimised out)");
    return loc;
  }
  // The location of a uniform the program may leave out (a variant's #if removes it); -1 then,
  // which glUniform* ignores.
  GLint optional(const char* uniform) const { return glGetUniformLocation(program_.id(), uniform); }

 private:
  const Program& program_;
  std::string name_;
};

}  // namespace hv::gpu
