// gmslab core: the one error type for bad input.
//
// Every loader and validator throws InputError with a message that names *where* (file, line,
// key path) and *what would be accepted*, so a user can fix the input without reading the code.
#pragma once

#include <stdexcept>
#include <string>

namespace gmslab {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A simulation that cannot go on (non-finite state, energy growing in a passive setup).
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace gmslab
