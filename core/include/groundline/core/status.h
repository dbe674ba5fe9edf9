// Status and Result<T>: the second tier of errors (see STYLE.md), for failures
// that depend on data: a malformed file, a degenerate geometry, a solver that
// did not converge. Contract violations are asserts, not statuses.
//
// A message names the input (file, line, field, message) and says what was
// expected, e.g. "ground_truth.tum:12: field 'qw': expected a finite number, got 'nan'".
#ifndef GROUNDLINE_CORE_STATUS_H_
#define GROUNDLINE_CORE_STATUS_H_

#include <cassert>
#include <optional>
#include <string>
#include <utility>

namespace groundline::core {

class [[nodiscard]] Status {
 public:
  static Status Ok() { return Status(); }
  static Status Error(std::string message) { return Status(std::move(message)); }

  bool ok() const { return !message_.has_value(); }
  // Empty for an ok status.
  const std::string& message() const {
    static const std::string kEmpty;
    return message_ ? *message_ : kEmpty;
  }
  // Prefixes context to an error ("while reading manifest.yaml: ..."); no-op if ok.
  Status WithContext(const std::string& context) const {
    if (ok()) return *this;
    return Error(context + ": " + *message_);
  }

 private:
  Status() = default;
  explicit Status(std::string message) : message_(std::move(message)) {}
  std::optional<std::string> message_;
};

// Either a value or an error Status. Accessing value() of an error is a
// contract violation.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)), status_(Status::Ok()) {}  // NOLINT: implicit
  Result(Status status) : status_(std::move(status)) {                  // NOLINT: implicit
    assert(!status_.ok() && "Result constructed from an ok Status without a value");
  }

  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }
  const std::string& message() const { return status_.message(); }

  const T& value() const& {
    assert(ok());
    return *value_;
  }
  T& value() & {
    assert(ok());
    return *value_;
  }
  T&& value() && {
    assert(ok());
    return std::move(*value_);
  }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

 private:
  std::optional<T> value_;
  Status status_;
};

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_STATUS_H_
