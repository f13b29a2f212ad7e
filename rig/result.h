// Result<T> carries either a value or an Error, so that recoverable failures (a malformed log
// line, a frame the bus refuses) travel as ordinary values the caller must look at. An Error's
// code is what a caller decides on (a stop request, a link the peer broke); its message is for
// people. Asking a Result for the wrong alternative is a programming error and aborts via
// HILRIG_CHECK.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "rig/check.h"

namespace hilrig::rig {

// The kinds of failure a caller handles differently; most errors only need their message.
enum class ErrorCode {
  kUnspecified,   // the message says it all
  kIo,            // an operating-system call failed (errno in the message)
  kTimeout,       // a deadline passed without an answer
  kInterrupted,   // a stop request ended the work early; nothing was kept
  kLinkClosed,    // the peer closed the connection
  kLinkProtocol,  // the peer sent what the link protocol refuses; `subcode` says what
};

struct Error {
  std::string message;
  ErrorCode code = ErrorCode::kUnspecified;
  // A finer code the layer that made the error defines under `code` (kLinkProtocol: a
  // host::LinkErrorKind), so it survives layers that only pass the error on.
  int subcode = 0;
};

inline Error MakeError(std::string message) { return Error{std::move(message)}; }
inline Error MakeError(ErrorCode code, std::string message) {
  return Error{std::move(message), code};
}

// `error` with `context` (a path, the step that failed) before its message; its codes stay.
inline Error InContext(const std::string& context, Error error) {
  error.message.insert(0, context);
  return error;
}

template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : storage_(std::in_place_index<0>, std::move(value)) {}
  Result(Error error) : storage_(std::in_place_index<1>, std::move(error)) {}

  bool ok() const { return storage_.index() == 0; }
  explicit operator bool() const { return ok(); }

  const T& value() const& {
    CheckOk();
    return *std::get_if<0>(&storage_);
  }
  T& value() & {
    CheckOk();
    return *std::get_if<0>(&storage_);
  }
  T&& value() && {
    CheckOk();
    return std::move(*std::get_if<0>(&storage_));
  }
  const Error& error() const {
    HILRIG_CHECK(!ok(), "error() called on a Result that holds a value");
    return *std::get_if<1>(&storage_);
  }

 private:
  void CheckOk() const {
    if (!ok()) [[unlikely]] {
      check_internal::Fail("ok()", error().message, HILRIG_SOURCE_FILE, __LINE__);
    }
  }

  std::variant<T, Error> storage_;
};

template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error error) : error_(std::move(error)) {}

  bool ok() const { return !error_.has_value(); }
  explicit operator bool() const { return ok(); }

  const Error& error() const {
    HILRIG_CHECK(!ok(), "error() called on a successful Result<void>");
    return *error_;
  }

 private:
  std::optional<Error> error_;
};

}  // namespace hilrig::rig
