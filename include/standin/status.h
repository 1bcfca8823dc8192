// Errors that come from outside the program (files, options, the GPU) travel as a Status; the
// library never prints and never exits. Programmer errors are asserts.
#pragma once

#include <cassert>
#include <optional>
#include <string>
#include <utility>

namespace standin {

enum class StatusCode {
    ok = 0,
    invalid_argument, // an option or parameter out of range
    not_found,        // a file or entry that is not there
    io_error,         // reading or writing failed
    bad_data,         // a file that exists but is corrupt, empty, or not understood
    unsupported,      // a format, version or feature we do not handle
    gpu_error,        // no suitable OpenGL context, shader compile failure, ...
};

class [[nodiscard]] Status {
public:
    Status() = default;
    Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

    static Status ok() { return {}; }
    bool is_ok() const { return code_ == StatusCode::ok; }
    explicit operator bool() const { return is_ok(); }
    StatusCode code() const { return code_; }
    // One line, naming the file or field and the problem.
    const std::string& message() const { return message_; }

private:
    StatusCode code_ = StatusCode::ok;
    std::string message_;
};

inline Status error(StatusCode code, std::string message) { return Status(code, std::move(message)); }

// A value or the Status that explains why there is none (std::expected is C++23).
template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : value_(std::move(value)) {}
    Result(Status status) : status_(std::move(status)) { assert(!status_.is_ok()); }

    bool is_ok() const { return value_.has_value(); }
    explicit operator bool() const { return is_ok(); }
    const Status& status() const { return status_; }
    T& value() { assert(value_); return *value_; }
    const T& value() const { assert(value_); return *value_; }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() { return value(); }
    const T& operator*() const { return value(); }

private:
    std::optional<T> value_;
    Status status_;
};

} // namespace standin

// Propagate a failed Status from an expression returning Status.
#define STANDIN_RETURN_IF_ERROR(expr)                 \
    do {                                               \
        ::standin::Status standin_status_ = (expr);    \
        if (!standin_status_.is_ok()) return standin_status_; \
    } while (0)
