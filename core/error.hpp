// gmslab core: typed errors. Every failure is one of five kinds, and the command line maps the
// kind to its exit code (README: 2 bad input, 3 the simulation diverged, 130 cancelled, 1 any other
// failure).
//
// Every loader and validator throws InputError with a message that names *where* (file, line,
// key path) and *what would be accepted*, so a user can fix the input without reading the code.
// All derive from std::runtime_error (and from Error, which carries the kind).
#pragma once

#include <stdexcept>
#include <string>

namespace gmslab {

enum class ErrorKind {
  Input,       // bad input: a file, key, option or value outside what is accepted
  Simulation,  // a simulation that cannot go on (non-finite state, energy growing)
  Io,          // a file that cannot be written (or a folder created): disk, permissions
  Internal,    // a bug: an invariant of the program does not hold
  Cancelled,   // a run stopped on request (an identification's cancel flag)
};

class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& what) : std::runtime_error(what), kind_(kind) {}
  ErrorKind kind() const { return kind_; }

 private:
  ErrorKind kind_;
};

class InputError : public Error {
 public:
  explicit InputError(const std::string& what) : Error(ErrorKind::Input, what) {}
};

// A simulation that cannot go on (non-finite state, energy growing in a passive setup).
class SimulationError : public Error {
 public:
  explicit SimulationError(const std::string& what) : Error(ErrorKind::Simulation, what) {}
};

// Output that cannot be written (atomic saves, folders); the message names the path and the
// system's reason.
class IoError : public Error {
 public:
  explicit IoError(const std::string& what) : Error(ErrorKind::Io, what) {}
};

class InternalError : public Error {
 public:
  explicit InternalError(const std::string& what) : Error(ErrorKind::Internal, what) {}
};

// Raises an Error of kind k with this message (InputError, SimulationError, IoError, InternalError;
// Error itself for Cancelled).
[[noreturn]] inline void throw_error(ErrorKind k, const std::string& what) {
  switch (k) {
    case ErrorKind::Input: throw InputError(what);
    case ErrorKind::Simulation: throw SimulationError(what);
    case ErrorKind::Io: throw IoError(what);
    case ErrorKind::Internal: throw InternalError(what);
    case ErrorKind::Cancelled: throw Error(ErrorKind::Cancelled, what);
  }
  throw InternalError(what);
}

// The command line's exit code for a failure of this kind: Input 2, Simulation 3, Cancelled 130 (as
// a shell reports a command stopped by Ctrl-C), Io and Internal 1 (an exception that is not an
// Error counts as Internal).
constexpr int exit_code(ErrorKind k) {
  return k == ErrorKind::Input ? 2 : k == ErrorKind::Simulation ? 3 : k == ErrorKind::Cancelled ? 130 : 1;
}
// How the command line introduces the message: "error", "simulation stopped", "cannot write",
// "cancelled", "internal error".
constexpr const char* error_label(ErrorKind k) {
  return k == ErrorKind::Input        ? "error"
         : k == ErrorKind::Simulation ? "simulation stopped"
         : k == ErrorKind::Io         ? "cannot write"
         : k == ErrorKind::Cancelled  ? "cancelled"
                                      : "internal error";
}

}  // namespace gmslab
