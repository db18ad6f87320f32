// Status: the outcome of an operation at a boundary (files, user input),
// either ok or one sentence saying what is wrong. Errors are values here;
// nothing in the sim layer throws across its API.
#pragma once

#include <string>
#include <utility>

namespace tumble::sim {

class Status {
 public:
  Status() = default;  // ok
  static Status error(std::string message) { return Status(std::move(message)); }

  bool ok() const { return !failed_; }
  const std::string& message() const { return message_; }

 private:
  explicit Status(std::string message) : message_(std::move(message)), failed_(true) {}

  std::string message_;
  bool failed_ = false;
};

}  // namespace tumble::sim
