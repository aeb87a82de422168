#pragma once
// The one exception type Sightline throws across I/O and validation boundaries.
//
// Its message is a single line a user can act on ("scene.glb: buffer 0 URI '../x.bin' escapes the
// file's folder"), never a stack of internal detail. Internal invariants use assert() instead.

#include <new>
#include <stdexcept>
#include <string>

namespace sightline {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// The one line a top-level handler shows for `e`, caught while `doing` ("running shaft on
/// p.json"). The standard library's own messages ("std::bad_alloc", "vector::_M_default_append")
/// say nothing a user can act on; running out of memory is said in words, with what was asked.
inline std::string describeFailure(const std::exception& e, const std::string& doing)
{
    if (dynamic_cast<const std::bad_alloc*>(&e) || dynamic_cast<const std::length_error*>(&e))
        return "out of memory while " + doing + " (ask for fewer samples, frames or pixels)";
    return e.what();
}

} // namespace sightline
