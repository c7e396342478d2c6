// SHA-256 (FIPS 180-4) of bytes, by OpenSSL's libcrypto: the fingerprint a
// run's provenance keeps of its model file.
#pragma once

#include <string>
#include <vector>

namespace ipmc {

// The digest of `bytes` as 64 lowercase hex digits.
std::string Sha256Hex(const std::string& bytes);

// The digest of `fields`, each written as "LENGTH:FIELD" so that fields
// cannot run together: a journal record's checksum.
std::string Sha256OfFields(const std::vector<std::string>& fields);

}  // namespace ipmc
