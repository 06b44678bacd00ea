#pragma once
// vx::Result<T> and vx::Status: how every recoverable failure (I/O, corrupt data, bad input, a
// missing driver) reaches callers, as a value with a one-line message. vx throws no exceptions.
// Public and self-contained (std only): the engine's own code uses the same types
// (world/base/result.h forwards here). Plain values: not thread-safe, copy them freely.

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace vx {

namespace detail {
// Reading the value of an error (or the error of a value) is a programming error: abort loudly.
[[noreturn]] inline void result_misuse(const char* what) {
    std::fprintf(stderr, "vx: %s\n", what);
    std::fflush(stderr);
    std::abort();
}
} // namespace detail

struct Error {
    std::string message; // One line, meant for the user.
};

// Result<T>: either a T or an Error.
template <class T> class Result {
public:
    Result(T value) : m_value(std::move(value)) {}
    Result(Error error) : m_value(std::move(error)) {}

    bool ok() const { return std::holds_alternative<T>(m_value); }
    explicit operator bool() const { return ok(); }

    T& value() {
        if (!ok())
            detail::result_misuse("Result::value() called on an error");
        return std::get<T>(m_value);
    }
    const T& value() const {
        if (!ok())
            detail::result_misuse("Result::value() called on an error");
        return std::get<T>(m_value);
    }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() { return value(); }
    const T& operator*() const { return value(); }

    // The message; only when !ok().
    const std::string& error() const {
        if (ok())
            detail::result_misuse("Result::error() called on a value");
        return std::get<Error>(m_value).message;
    }

private:
    std::variant<T, Error> m_value;
};

// Status: success or an error message.
class Status {
public:
    Status() = default;
    Status(Error error) : m_error(std::move(error.message)) {}
    static Status success() { return {}; }

    bool ok() const { return !m_error.has_value(); }
    explicit operator bool() const { return ok(); }
    // The message; only when !ok().
    const std::string& error() const {
        if (!m_error)
            detail::result_misuse("Status::error() called on success");
        return *m_error;
    }

private:
    std::optional<std::string> m_error;
};

} // namespace vx
