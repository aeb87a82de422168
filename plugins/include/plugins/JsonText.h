#pragma once
// The one way Sightline parses untrusted JSON text (glTF documents, project files): nesting depth is
// checked before the parser runs (base/JsonDepth.h), and every parser failure becomes one
// sightline::Error naming the file, what is wrong in words and where, never nlohmann's bracketed
// exception ids.

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace sightline {

/// Parses `text` (strict: one value, nothing after it but whitespace). Throws sightline::Error
/// "<what>: invalid JSON: <reason>, at byte N" on malformed or over-deep input or on numbers beyond
/// double's range.
nlohmann::json parseJsonText(std::string_view text, const std::string& what);

} // namespace sightline
