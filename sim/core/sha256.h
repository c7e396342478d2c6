// SHA-256 (FIPS 180-4) of bytes, by OpenSSL's libcrypto: the fingerprint a
// run's provenance keeps of its model file.
#pragma once

#include <string>

namespace ipmc {

// The digest of `bytes` as 64 lowercase hex digits.
std::string Sha256Hex(const std::string& bytes);

}  // namespace ipmc
