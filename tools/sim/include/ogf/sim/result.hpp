// How every ogf_sim function reports failure: a value or an error message that names the file, the line
// or the field that was wrong (std::expected is C++23; this is the small subset the simulator needs).
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace ogf::sim {

struct Error {
  std::string message;
};

template <class T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}          // NOLINT(google-explicit-constructor)
  Result(Error error) : v_(std::move(error)) {}      // NOLINT(google-explicit-constructor)

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() { return std::get<0>(v_); }
  const T& value() const { return std::get<0>(v_); }
  T& operator*() { return value(); }
  const T& operator*() const { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  const std::string& error() const { return std::get<1>(v_).message; }

 private:
  std::variant<T, Error> v_;
};

struct Ok {};
// The result of an operation that produces nothing but may fail (writing a file, say).
using Status = Result<Ok>;

}  // namespace ogf::sim
