#pragma once
/// \file
/// SHA-256 digests: the provenance of baked sphere sets (the source mesh's file), and the
/// keys of what is kept on disk to be read back instead of recomputed.

#include <string>

namespace medspheres {

/// The SHA-256 of the bytes of \p path, as 64 lowercase hex digits.
/// \throws InputError when the file cannot be read.
std::string file_sha256(const std::string& path);

/// The SHA-256 of \p bytes, as 64 lowercase hex digits.
std::string sha256_hex(const std::string& bytes);

}  // namespace medspheres
