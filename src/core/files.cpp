// Reading files from outside and writing outputs (files.h): regular files only, opened without
// blocking and size-checked before allocation; outputs written to a temporary name beside their
// final path and renamed (directories exchanged atomically), never over an input, never into a
// folder that does not exist.
#include <standin/files.h>
#include <standin/limits.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#ifndef RENAME_EXCHANGE
#define RENAME_EXCHANGE (1 << 1)
#endif

namespace standin {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Names in messages

static void append_escaped(std::string& out, unsigned char c)
{
    switch (c) {
    case '\n': out += "\\n"; return;
    case '\r': out += "\\r"; return;
    case '\t': out += "\\t"; return;
    default: break;
    }
    char hex[8];
    std::snprintf(hex, sizeof hex, "\\x%02x", c);
    out += hex;
}

static bool is_control(unsigned char c) { return c < 0x20 || c == 0x7f; }

std::string quoted(const std::string& path)
{
    bool plain = !path.empty();
    for (unsigned char c : path)
        if (is_control(c) || c == ' ' || c == '"' || c == '\'' || c == '\\') plain = false;
    if (plain) return path;
    std::string out = "\"";
    for (unsigned char c : path) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += char(c);
        } else if (is_control(c)) {
            append_escaped(out, c);
        } else {
            out += char(c);
        }
    }
    return out + "\"";
}

std::string one_line(std::string_view text, std::size_t max_length)
{
    std::string out;
    for (unsigned char c : text) {
        if (is_control(c)) append_escaped(out, c);
        else out += char(c);
    }
    if (out.size() > max_length) out = out.substr(0, max_length > 3 ? max_length - 3 : 0) + "...";
    return out;
}

Status naming_file(const Status& status, const std::string& path)
{
    if (status.is_ok()) return status;
    const std::string& message = status.message();
    std::string name = quoted(path);
    if (message.find(name) != std::string::npos || message.find(path) != std::string::npos) return status;
    return error(status.code(), name + ": " + message);
}

// ---------------------------------------------------------------------------------------------
// Reading

// The refusal for a stat/open failure with errno `e`.
static Status open_error(const std::string& path, int e)
{
    std::string name = quoted(path);
    switch (e) {
    case ENOENT: {
        struct stat link {};
        if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode))
            return error(StatusCode::not_found, name + ": is a symbolic link to nothing (no such file)");
        return error(StatusCode::not_found, name + ": no such file");
    }
    case ENOTDIR: return error(StatusCode::not_found, name + ": no such file (a part of the path is not a folder)");
    case ELOOP: return error(StatusCode::bad_data, name + ": symbolic link loop (too many levels of links)");
    case ENAMETOOLONG: return error(StatusCode::bad_data, one_line(name, 200) + ": file name too long for the system");
    case EACCES: return error(StatusCode::io_error, name + ": permission denied");
    default: return error(StatusCode::io_error, name + ": cannot open: " + std::strerror(e));
    }
}

// ok for a regular file, else what it is instead.
static Status check_type(const std::string& path, mode_t mode)
{
    if (S_ISREG(mode)) return Status::ok();
    const char* what = S_ISDIR(mode) ? "is a directory, expected a file"
                       : S_ISFIFO(mode) ? "is a FIFO (named pipe), not a regular file"
                       : S_ISSOCK(mode) ? "is a socket, not a regular file"
                       : S_ISCHR(mode) || S_ISBLK(mode) ? "is a device, not a regular file"
                                                        : "is not a regular file";
    return error(StatusCode::bad_data, quoted(path) + ": " + what);
}

Status check_regular_file(const std::string& path)
{
    if (path.empty()) return error(StatusCode::not_found, "\"\": no such file (empty file name)");
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return open_error(path, errno);
    return check_type(path, st.st_mode);
}

Status check_directory(const std::string& path)
{
    if (path.empty()) return error(StatusCode::not_found, "\"\": no such directory (empty name)");
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return open_error(path, errno);
    if (!S_ISDIR(st.st_mode)) return error(StatusCode::bad_data, quoted(path) + ": is not a directory");
    return Status::ok();
}

// Reads up to `limit` bytes (all of a file no larger; a larger one refused when `refuse_larger`).
static Result<std::string> read_regular(const std::string& path, std::uint64_t limit, bool refuse_larger, bool budget_limit)
{
    // stat first: devices are refused without being opened at all
    STANDIN_RETURN_IF_ERROR(check_regular_file(path));
    // O_NONBLOCK: had the file been swapped for a FIFO since, opening it must not wait for a writer
    int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return open_error(path, errno);
    struct stat st {};
    Status status = ::fstat(fd, &st) == 0 ? check_type(path, st.st_mode) : open_error(path, errno);
    bool budget_limit_used = budget_limit;
    if (status && refuse_larger && std::uint64_t(st.st_size) > limit)
        status = error(StatusCode::bad_data, quoted(path) + ": " + bytes_text(std::uint64_t(st.st_size)) +
                                                 " is more than the " + bytes_text(limit) + " this reader accepts" +
                                                 (budget_limit_used ? " (the memory budget; STANDIN_MEMORY_LIMIT raises it)" : ""));
    std::string bytes;
    if (status) {
        bytes.resize(std::size_t(std::min<std::uint64_t>(std::uint64_t(st.st_size), limit)));
        std::size_t done = 0;
        while (done < bytes.size()) {
            ssize_t got = ::read(fd, bytes.data() + done, bytes.size() - done);
            if (got < 0 && errno == EINTR) continue;
            if (got < 0) {
                status = error(StatusCode::io_error, quoted(path) + ": read failed: " + std::strerror(errno));
                break;
            }
            if (got == 0) break; // shrunk while reading
            done += std::size_t(got);
        }
        bytes.resize(done);
    }
    ::close(fd);
    if (!status) return status;
    return bytes;
}

Result<std::string> read_file(const std::string& path, std::uint64_t max_bytes)
{
    return read_regular(path, max_bytes > 0 ? max_bytes : budget().memory_bytes, true, max_bytes == 0);
}

Result<std::string> read_file_head(const std::string& path, std::size_t bytes)
{
    return read_regular(path, bytes, false, false);
}

// ---------------------------------------------------------------------------------------------
// Outputs

std::string temporary_path_for(const std::string& final_path)
{
    static std::atomic<unsigned> counter{0};
    return final_path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
}

// The process id in "FINAL.tmpPID_N..." when `name` is a temporary of `base`, else 0.
static pid_t temporary_owner(const std::string& name, const std::string& base)
{
    std::string prefix = base + ".tmp";
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return 0;
    std::size_t i = prefix.size();
    long long pid = 0;
    while (i < name.size() && name[i] >= '0' && name[i] <= '9' && pid < (1ll << 31)) pid = pid * 10 + (name[i++] - '0');
    if (i == prefix.size() || i >= name.size() || name[i] != '_' || pid <= 0 || pid >= (1ll << 31)) return 0;
    return pid_t(pid);
}

void remove_stale_temporaries(const std::string& final_path)
{
    fs::path final(final_path);
    if (!final.has_filename()) final = final.parent_path();
    fs::path directory = final.parent_path().empty() ? fs::path(".") : final.parent_path();
    std::string base = final.filename().string();
    std::error_code ec;
    for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
        pid_t owner = temporary_owner(it->path().filename().string(), base);
        if (owner == 0 || owner == ::getpid()) continue;
        if (::kill(owner, 0) == 0 || errno != ESRCH) continue; // still running (or not ours to ask)
        std::error_code ignored;
        fs::remove_all(it->path(), ignored);
    }
}

Status check_output_path(const std::string& output)
{
    if (output.empty()) return error(StatusCode::invalid_argument, "an output needs a file name");
    fs::path path(output);
    if (!path.has_filename()) path = path.parent_path();
    fs::path parent = path.parent_path();
    if (parent.empty()) return Status::ok();
    struct stat st {};
    if (::stat(parent.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        return error(StatusCode::invalid_argument, quoted(output) + ": the folder " + quoted(parent.string()) +
                                                       " does not exist (outputs never create folders)");
    return Status::ok();
}

static bool same_file(const struct stat& a, const struct stat& b) { return a.st_dev == b.st_dev && a.st_ino == b.st_ino; }

// Whether `path`, or a folder above it (links resolved), is the file `folder`.
static bool is_within(const std::string& path, const struct stat& folder)
{
    std::error_code ec;
    fs::path real = fs::weakly_canonical(fs::absolute(path, ec), ec);
    if (ec) return false;
    for (fs::path p = real.parent_path(); !p.empty(); p = p.parent_path()) {
        struct stat f {};
        if (::stat(p.c_str(), &f) == 0 && same_file(f, folder)) return true;
        if (p == p.root_path()) break;
    }
    return false;
}

Status check_output_is_not_input(const std::string& output, const std::vector<std::string>& inputs)
{
    struct stat out {};
    bool output_exists = ::stat(output.c_str(), &out) == 0;
    for (const std::string& input : inputs) {
        struct stat in {};
        if (input.empty() || ::stat(input.c_str(), &in) != 0) continue;
        if (output_exists && same_file(out, in))
            return error(StatusCode::invalid_argument, quoted(output) + ": is the input " + quoted(input) +
                                                           "; an output never replaces an input");
        if (S_ISDIR(in.st_mode) && is_within(output, in))
            return error(StatusCode::invalid_argument, quoted(output) + ": is inside the input " + quoted(input) +
                                                           "; an output never writes into an input");
        if (output_exists && S_ISDIR(out.st_mode) && is_within(input, out))
            return error(StatusCode::invalid_argument, quoted(output) + ": holds the input " + quoted(input) +
                                                           "; an output never replaces an input");
    }
    return Status::ok();
}

Status write_file_atomic(const std::string& path, std::string_view contents)
{
    STANDIN_RETURN_IF_ERROR(check_output_path(path));
    std::string temporary = temporary_path_for(path);
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) return error(StatusCode::io_error, quoted(path) + ": cannot open for writing");
        out.write(contents.data(), std::streamsize(contents.size()));
        out.flush();
        if (!out) {
            out.close();
            std::error_code ignored;
            fs::remove(temporary, ignored);
            return error(StatusCode::io_error, quoted(path) + ": write failed (disk full?)");
        }
    }
    return commit_path(temporary, path);
}

// renameat2(RENAME_EXCHANGE) through syscall(): glibc has had the wrapper only since 2.28.
static bool exchange_paths(const std::string& a, const std::string& b, int* failure)
{
    if (::syscall(SYS_renameat2, AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0) return true;
    *failure = errno;
    return false;
}

// Where the filesystem cannot exchange: the old directory aside, the new one in, the old one gone.
static Status replace_by_two_renames(const std::string& temporary, const std::string& final_path)
{
    std::error_code ec;
    std::string old = temporary_path_for(final_path) + ".old";
    fs::rename(final_path, old, ec);
    if (ec) return error(StatusCode::io_error, quoted(final_path) + ": cannot replace: " + ec.message());
    fs::rename(temporary, final_path, ec);
    if (ec) {
        std::error_code ignored;
        fs::rename(old, final_path, ignored);
        return error(StatusCode::io_error, quoted(final_path) + ": cannot rename into place: " + ec.message());
    }
    fs::remove_all(old, ec);
    return Status::ok();
}

Status commit_path(const std::string& temporary, const std::string& final_path)
{
    std::error_code ec;
    if (fs::is_directory(temporary, ec) && fs::exists(final_path, ec)) {
        // one atomic step: the new directory in, the old one at the temporary name, then removed
        int failure = 0;
        if (exchange_paths(temporary, final_path, &failure)) {
            fs::remove_all(temporary, ec);
            return Status::ok();
        }
        if (failure == EINVAL || failure == ENOSYS || failure == EOPNOTSUPP || failure == EPERM)
            return replace_by_two_renames(temporary, final_path);
        std::error_code ignored;
        fs::remove_all(temporary, ignored);
        return error(StatusCode::io_error, quoted(final_path) + ": cannot replace: " + std::strerror(failure));
    }
    fs::rename(temporary, final_path, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove_all(temporary, ignored);
        return error(StatusCode::io_error, quoted(final_path) + ": cannot rename into place: " + ec.message());
    }
    return Status::ok();
}

bool json_nesting_within(std::string_view text, int max_depth)
{
    int depth = 0;
    bool in_string = false, escaped = false;
    for (char c : text) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_depth) return false;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return true;
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
