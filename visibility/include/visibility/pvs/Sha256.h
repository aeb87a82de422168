#pragma once
// SHA-256 (OpenSSL's libcrypto) as lower-case hex: scene identity in .pvs files and part manifests.

#include <string>
#include <string_view>

namespace sightline::pvs {

std::string sha256Hex(std::string_view bytes);

} // namespace sightline::pvs
