#pragma once
// The one exception type Sightline throws across I/O and validation boundaries.
//
// Its message is a single line a user can act on ("scene.glb: buffer 0 URI '../x.bin' escapes the
// file's folder"), never a stack of internal detail. Internal invariants use assert() instead.

#include <stdexcept>
#include <string>

namespace sightline {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

} // namespace sightline
