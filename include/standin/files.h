// Writing files so that a reader never sees half of one: everything goes to a temporary name in
// the same directory and is renamed into place once complete.
#pragma once

#include <standin/status.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace standin {

// A temporary path next to `final_path`, unique to this process.
std::string temporary_path_for(const std::string& final_path);

Status write_file_atomic(const std::string& path, std::string_view contents);
Result<std::string> read_file(const std::string& path);

// Renames a finished temporary file or directory into place, replacing an older one.
Status commit_path(const std::string& temporary, const std::string& final_path);

// FNV-1a 64-bit: identity hashes of source models and package contents (not for security).
std::uint64_t hash_bytes(std::string_view bytes, std::uint64_t seed = 0xcbf29ce484222325ull);
std::string hex64(std::uint64_t value);

} // namespace standin
