#pragma once
// SHA-256 (FIPS 180-4), to tie a calibration report to the model file written with it: the
// report records the model's digest, which `sha256sum` or `kincal verify` can check.

#include <string>

namespace kincal {

/// The SHA-256 digest of `data` as 64 lowercase hexadecimal digits.
std::string sha256_hex(const std::string& data);

/// The SHA-256 of model file `path`'s bytes, read within the model-file limit (JsonLimits:
/// /dev/zero or a huge file fails at once). Throws std::invalid_argument naming the file.
std::string model_file_sha256(const std::string& path);

}  // namespace kincal
