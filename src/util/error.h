// error.h — the one exception type for bad input. Its message is already the
// one line a user sees: "FILE: WHERE: PROBLEM" (WHERE is a line:column or a
// JSON path, and is left out when there is no better place than the file).
#pragma once

#include <stdexcept>
#include <string>

namespace wp {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Errors of the GPU or the environment (no device, out of memory, truncated
// traversal): not the user's input, but still one clear line and no output.
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace wp
