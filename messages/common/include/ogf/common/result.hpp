// How every ogf library reports failure: a Result<T> holds a value or an Error (error.hpp) whose kind says
// what sort of failure it is and whose message names the file, offset, line or field that was wrong
// (std::expected is C++23). Libraries never print or exit; programs report the message once and pick the
// exit code by the kind.
#pragma once

#include <utility>
#include <variant>

#include "ogf/common/error.hpp"

namespace ogf {

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}      // NOLINT(google-explicit-constructor): implicit by design
  Result(Error error) : v_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return std::holds_alternative<T>(v_); }
  explicit operator bool() const { return ok(); }

  T& value() & { return std::get<T>(v_); }
  const T& value() const& { return std::get<T>(v_); }
  T&& value() && { return std::get<T>(std::move(v_)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

  const Error& error() const { return std::get<Error>(v_); }

 private:
  std::variant<T, Error> v_;
};

// A Result without a value: success, or an Error.
struct Ok {};
using Status = Result<Ok>;

inline Status okStatus() { return Ok{}; }

}  // namespace ogf
