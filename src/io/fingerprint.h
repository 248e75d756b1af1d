// Fingerprints that say whether files of an earlier stage still belong to a case: a 64-bit
// FNV-1a hash as 16 hexadecimal digits (not cryptographic: it detects changes).
#pragma once

#include <string>

namespace stickslip {

// Of `text`.
std::string fingerprint_hex(const std::string& text);
// Of a file's bytes; InvalidInput{path} if it cannot be read.
std::string file_fingerprint_hex(const std::string& path);

}  // namespace stickslip
