// Files from outside and files we write. Reading: only regular files are read (no FIFOs, devices or
// directories, which would block or never end), symlinks are followed once by the kernel and loops
// refused, and the size is checked against a limit before anything is allocated. Writing: nothing
// half-written is ever seen (a temporary name beside the final path, renamed into place), an output
// never replaces an input of the same command, and its parent directory must already exist.
#pragma once

#include <standin/status.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace standin {

// A file name as messages show it: unchanged when it is plain (printable, no spaces, quotes or
// backslashes), else in double quotes with C escapes (\n, \", \\, \xHH), so that a name holding a
// newline keeps its message on one line.
std::string quoted(const std::string& path);
// (std::quoted, found by argument-dependent lookup, would be a better match for a non-const string)
inline std::string quoted(std::string& path) { return quoted(static_cast<const std::string&>(path)); }

// A message made to fit one line: control characters escaped as in quoted(), at most `max_length`
// characters (cut with "...").
std::string one_line(std::string_view text, std::size_t max_length = 1000);

// `status` with its message naming `path` first ("PATH: MESSAGE") unless it already names it: for
// errors that come back from a layer that does not know the file (a renderer, a baker).
Status naming_file(const Status& status, const std::string& path);

// Whether `path` names a regular file that can be read: ok, or not_found (no such file, a dangling
// link), bad_data (a directory, FIFO, socket or device; a symlink loop; a name too long), each naming
// the file. Checks without opening, for files a third-party reader opens itself.
Status check_regular_file(const std::string& path);
// The same for a directory (a package): not_found, or bad_data for anything else, naming it.
Status check_directory(const std::string& path);

// Reads a whole regular file (see check_regular_file; opened without blocking, so a FIFO is refused,
// not waited on). A file larger than `max_bytes` is refused before reading, naming the limit; the
// default is the memory budget (limits.h).
Result<std::string> read_file(const std::string& path, std::uint64_t max_bytes = 0);
// The first `bytes` bytes of a regular file (fewer when it is shorter), with the same checks.
Result<std::string> read_file_head(const std::string& path, std::size_t bytes);

// A temporary path next to `final_path`, unique to this process: FINAL.tmpPID_N.
std::string temporary_path_for(const std::string& final_path);

// Removes FINAL.tmpPID_N[...] entries beside `final_path` left by processes that no longer run
// (killed during a write). Entries of running processes are left alone. Never fails.
void remove_stale_temporaries(const std::string& final_path);

// The rule for every output: its parent directory exists (nothing is created on the way), and the
// output is not an existing directory. invalid_argument naming the output otherwise.
Status check_output_path(const std::string& output);

// The other rule for every output: it is not one of `inputs`, not inside an input directory (a
// package), and, when it is a directory to be replaced (a package, a report), holds no input;
// compared by filesystem identity (device and inode: links and other spellings of the same file
// count). Inputs that do not exist are ignored. invalid_argument naming both otherwise.
Status check_output_is_not_input(const std::string& output, const std::vector<std::string>& inputs);

Status write_file_atomic(const std::string& path, std::string_view contents);

// Renames a finished temporary file or directory into place, replacing an older one. A directory
// replaces an existing one in one atomic exchange (renameat2 RENAME_EXCHANGE) so that a kill at any
// moment leaves the old or the new one; only where the filesystem refuses the exchange are there
// two renames.
Status commit_path(const std::string& temporary, const std::string& final_path);

// Whether JSON text nests arrays and objects at most `max_depth` deep (outside strings): checked
// before parsing a file from outside, whose deep nesting would recurse in the parser's callers.
bool json_nesting_within(std::string_view text, int max_depth);

// FNV-1a 64-bit: identity hashes of source models and package contents (not for security).
std::uint64_t hash_bytes(std::string_view bytes, std::uint64_t seed = 0xcbf29ce484222325ull);
std::string hex64(std::uint64_t value);

} // namespace standin
