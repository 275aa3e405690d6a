#pragma once
// Recoverable errors: the library returns Result<T> carrying an Error with context; only the CLI
// turns errors into exit codes (see cli/exit_codes.h).
#include <fmt/format.h>

#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace relief {

enum class ErrorKind {
    BadArgument = 1,   // a parameter or option value is out of range
    Io = 2,            // a file could not be opened, read or written
    InvalidInput = 3,  // a file was read but its content is corrupt or unusable
    Runtime = 4,       // runtime failure (GL context, compile, link)
    Unsupported = 5,   // a format or feature relief does not handle
};

struct Error {
    ErrorKind kind = ErrorKind::Runtime;
    std::string message;
};

template <class... Args>
Error makeError(ErrorKind kind, fmt::format_string<Args...> format, Args&&... args) {
    return Error{kind, fmt::format(format, std::forward<Args>(args)...)};
}

template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : m_value(std::move(value)) {}
    Result(Error error) : m_value(std::move(error)) {}

    bool ok() const { return std::holds_alternative<T>(m_value); }
    explicit operator bool() const { return ok(); }
    T& value() { return std::get<T>(m_value); }
    const T& value() const { return std::get<T>(m_value); }
    T& operator*() { return value(); }
    const T& operator*() const { return value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    const Error& error() const { return std::get<Error>(m_value); }

private:
    std::variant<T, Error> m_value;
};

// Result<void>: success or an Error.
class [[nodiscard]] Status {
public:
    Status() = default;
    Status(Error error) : m_error(std::move(error)) {}
    bool ok() const { return !m_error.has_value(); }
    explicit operator bool() const { return ok(); }
    const Error& error() const { return *m_error; }

private:
    std::optional<Error> m_error;
};

}  // namespace relief
