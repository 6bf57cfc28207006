#pragma once
// A stop asked for from outside the computation: the first of the signals
// the application catches (app/Run.hpp, install_stop_signal_handlers) is
// noted here, so that work below the application that may run long before
// the time loop starts (growing a random pack) can give up at once.
#include <csignal>
#include <stdexcept>
#include <string>

namespace poresph {

// Set by the signal handler (the first signal counts), read anywhere.
inline volatile std::sig_atomic_t stop_request = 0;

// Set-up work given up because a stop was asked for: there is no state yet
// to save, so the run ends with 128 + signal_number and writes nothing.
// what(): "while <what was being done>, before any particle was made: ...".
struct SetupInterrupted : std::runtime_error {
  SetupInterrupted(const std::string& what_was_done, int signal_number_)
      : std::runtime_error("while " + what_was_done + ", before any particle was made: nothing to save"),
        signal_number(signal_number_) {}
  int signal_number;
};

// Throws SetupInterrupted if a stop was asked for. `doing`: what the set-up
// was doing, for the message ("growing the random pack").
inline void stop_setup_if_asked(const char* doing) {
  const int signal_number = stop_request;
  if (signal_number != 0) throw SetupInterrupted(doing, signal_number);
}

}  // namespace poresph
