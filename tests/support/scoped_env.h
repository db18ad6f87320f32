// ScopedEnv: sets (or, given null, unsets) an environment variable for one
// scope and puts back what was there. Header-only, for the tests of what
// reads the environment (tokens, the default server); those that do not
// link tumble_test_support include it as "support/scoped_env.h".
#pragma once

#include <cstdlib>
#include <optional>
#include <string>

namespace tumble::test {

class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) {
      ::setenv(name, value, 1);
    } else {
      ::unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (old_) {
      ::setenv(name_, old_->c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace tumble::test
