// Atomic file writing and small file helpers: every output goes to a temporary name beside its
// final path and is renamed when complete, so a crash or an error never leaves half a file.
#include <standin/files.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace standin {

namespace fs = std::filesystem;

std::string temporary_path_for(const std::string& final_path)
{
    static std::atomic<unsigned> counter{0};
    return final_path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
}

Status write_file_atomic(const std::string& path, std::string_view contents)
{
    std::string temporary = temporary_path_for(path);
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) return error(StatusCode::io_error, path + ": cannot open for writing");
        out.write(contents.data(), std::streamsize(contents.size()));
        out.flush();
        if (!out) {
            out.close();
            std::error_code ignored;
            fs::remove(temporary, ignored);
            return error(StatusCode::io_error, path + ": write failed (disk full?)");
        }
    }
    return commit_path(temporary, path);
}

Result<std::string> read_file(const std::string& path)
{
    std::error_code ec;
    if (!fs::exists(path, ec)) return error(StatusCode::not_found, path + ": no such file");
    if (fs::is_directory(path, ec)) return error(StatusCode::bad_data, path + ": is a directory, expected a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) return error(StatusCode::io_error, path + ": cannot open for reading");
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) return error(StatusCode::io_error, path + ": read failed");
    return buffer.str();
}

Status commit_path(const std::string& temporary, const std::string& final_path)
{
    std::error_code ec;
    // Directories cannot be renamed over a non-empty directory: move the old one aside first.
    if (fs::is_directory(temporary, ec) && fs::exists(final_path, ec)) {
        std::string old = temporary_path_for(final_path) + ".old";
        fs::rename(final_path, old, ec);
        if (ec) return error(StatusCode::io_error, final_path + ": cannot replace: " + ec.message());
        fs::rename(temporary, final_path, ec);
        if (ec) {
            std::error_code ignored;
            fs::rename(old, final_path, ignored);
            return error(StatusCode::io_error, final_path + ": cannot rename into place: " + ec.message());
        }
        fs::remove_all(old, ec);
        return Status::ok();
    }
    fs::rename(temporary, final_path, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove_all(temporary, ignored);
        return error(StatusCode::io_error, final_path + ": cannot rename into place: " + ec.message());
    }
    return Status::ok();
}

std::uint64_t hash_bytes(std::string_view bytes, std::uint64_t seed)
{
    std::uint64_t h = seed;
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 0x100000001b3ull;
    }
    return h;
}

std::string hex64(std::uint64_t value)
{
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
    return text;
}

} // namespace standin
