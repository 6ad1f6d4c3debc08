#pragma once
// Host-side error types. BadInput is anything the user gave us that we cannot use (bad file, bad option
// value): it becomes a one-line "error: …" message and exit code 2.
#include <stdexcept>
#include <string>

namespace hmp {

class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace hmp
