#pragma once
// A value or an error message: how recoverable failures (I/O, corrupt data, bad input) reach callers.

#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "world/base/assert.h"

namespace vx {

struct Error {
    std::string message; // One line, meant for the user.
};

// Result<T>: either a T or an Error. Not thread-safe (a plain value).
template <class T> class Result {
public:
    Result(T value) : m_value(std::move(value)) {}
    Result(Error error) : m_value(std::move(error)) {}

    bool ok() const { return std::holds_alternative<T>(m_value); }
    explicit operator bool() const { return ok(); }

    T& value() {
        VX_ASSERT(ok());
        return std::get<T>(m_value);
    }
    const T& value() const {
        VX_ASSERT(ok());
        return std::get<T>(m_value);
    }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() { return value(); }
    const T& operator*() const { return value(); }

    const std::string& error() const {
        VX_ASSERT(!ok());
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
    const std::string& error() const {
        VX_ASSERT(!ok());
        return *m_error;
    }

private:
    std::optional<std::string> m_error;
};

} // namespace vx
