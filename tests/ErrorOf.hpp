#pragma once
// The message of the exception of type Error that `f` throws ("" if it
// throws none): what the tests of refusals compare with the expected text.
#include <string>
#include <utility>
#include <stdexcept>

namespace poresph::testing {

template <class Error = std::invalid_argument, class F>
std::string error_of(F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace poresph::testing
