#pragma once
// SHA-256 (FIPS 180-4), to tie a calibration report to the model file written with it: the
// report records the model's digest, which `sha256sum` or `kincal verify` can check.

#include <string>

namespace kincal::cli {

/// The SHA-256 digest of `data` as 64 lowercase hexadecimal digits.
std::string sha256_hex(const std::string& data);

}  // namespace kincal::cli
