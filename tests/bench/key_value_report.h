// The benchmarks' reports, read back by their smoke tests: a line (or a
// text) of key=value fields separated by spaces.
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>

namespace tumble::test {

using Report = std::map<std::string, std::string>;

// Every key=value field of `text`; a later key replaces an earlier one.
inline Report parse_report(const std::string& text) {
  Report report;
  std::istringstream fields(text);
  for (std::string field; fields >> field;) {
    const std::size_t equals = field.find('=');
    if (equals != std::string::npos) report[field.substr(0, equals)] = field.substr(equals + 1);
  }
  return report;
}

// The field `key` as a number; a test failure (and -1) when it is missing.
inline double number(const Report& report, const std::string& key) {
  const auto it = report.find(key);
  if (it == report.end()) {
    ADD_FAILURE() << "no " << key << " in the report";
    return -1;
  }
  return std::stod(it->second);
}

}  // namespace tumble::test
