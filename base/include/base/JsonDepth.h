#pragma once
// JSON parsers (nlohmann's DOM and its destructor's callers, tinygltf's conversion of `extras` into
// its own values, our own walks over a document) recurse once per nesting level, so a file of a few
// kilobytes of '[' can exhaust the stack. Every reader of untrusted JSON scans the text with
// checkJsonDepth first, before any parser sees it.

#include <cstddef>
#include <string>
#include <string_view>

namespace sightline {

/// The deepest nesting of arrays and objects Sightline reads. Real glTF and project files stay in
/// single digits; the limit leaves room for deep `extras` while keeping every recursive walk far from
/// the stack's end.
inline constexpr std::size_t kMaxJsonDepth = 512;

/// Throws sightline::Error ("<what>: JSON nested deeper than N levels, at byte B") when `text` nests
/// arrays or objects deeper than `maxDepth`. Brackets inside strings (escapes included) do not count.
/// It judges nesting only: malformed JSON is left to the parser to report.
void checkJsonDepth(std::string_view text, const std::string& what, std::size_t maxDepth = kMaxJsonDepth);

} // namespace sightline
