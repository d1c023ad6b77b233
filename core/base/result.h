#pragma once
/// Error reporting for core/: no exceptions. Fallible calls return a Status or a Result<T> that
/// carries a message meant for a person ("what is wrong and how to fix it").

#include <optional>
#include <string>
#include <utility>

namespace softtouch {

/// Success, or a failure with a human-readable message.
class [[nodiscard]] Status {
public:
    /// A successful status.
    static Status success() { return Status(); }
    /// A failed status with the given message.
    static Status error(std::string message) { return Status(std::move(message)); }
    /// A failure because the user stopped the work (a progress callback said no): callers that asked
    /// for it need not report it as an error. Tell it apart with wasCancelled(), not by the message.
    static Status cancelled(std::string message) {
        Status s(std::move(message));
        s.m_cancelled = true;
        return s;
    }

    /// True on success.
    bool ok() const { return !m_failed; }
    explicit operator bool() const { return ok(); }
    /// True when the failure is a cancellation (see cancelled()).
    bool wasCancelled() const { return m_cancelled; }
    /// The failure message; empty on success.
    const std::string& message() const { return m_message; }

private:
    Status() = default;
    explicit Status(std::string message) : m_failed(true), m_message(std::move(message)) {}
    bool m_failed = false;
    bool m_cancelled = false;
    std::string m_message;
};

/// A value, or a failure message.
template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : m_value(std::move(value)) {}  // NOLINT: implicit by design, like std::optional
    Result(Status failure) : m_message(failure.message()), m_cancelled(failure.wasCancelled()) {}  // NOLINT

    /// True when a value is held.
    bool ok() const { return m_value.has_value(); }
    explicit operator bool() const { return ok(); }
    /// The value; only valid when ok().
    T& value() { return *m_value; }
    const T& value() const { return *m_value; }
    T* operator->() { return &*m_value; }
    const T* operator->() const { return &*m_value; }
    /// The failure message; empty on success.
    const std::string& message() const { return m_message; }
    /// True when the failure is a cancellation (Status::cancelled()).
    bool wasCancelled() const { return m_cancelled; }
    /// The failure as a Status (kind kept); success when a value is held.
    Status status() const {
        if (ok())
            return Status::success();
        return m_cancelled ? Status::cancelled(m_message) : Status::error(m_message);
    }

private:
    std::optional<T> m_value;
    std::string m_message;
    bool m_cancelled = false;
};

}  // namespace softtouch
