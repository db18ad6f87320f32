#include "process_cpu.h"

#include <sched.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace tumble::bench {
namespace {

// The fields of a /proc stat file from field 3 on, so field n is at
// [n - 3]. The command name (field 2) is in parentheses and may hold
// spaces: the fields are counted from the last ')'. Empty when unreadable.
std::vector<std::string> stat_fields(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::string line;
  if (!std::getline(file, line)) return {};
  const std::size_t name_end = line.rfind(')');
  if (name_end == std::string::npos) return {};
  std::istringstream words(line.substr(name_end + 1));
  std::vector<std::string> fields;
  for (std::string field; words >> field;) fields.push_back(field);
  return fields;
}

// utime + stime (fields 14 and 15) in seconds; nullopt when missing.
std::optional<double> cpu_seconds(const std::vector<std::string>& fields) {
  if (fields.size() < 15 - 2) return std::nullopt;
  const unsigned long long ticks = std::stoull(fields[14 - 3]) + std::stoull(fields[15 - 3]);
  return static_cast<double>(ticks) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

}  // namespace

std::optional<double> process_cpu_seconds(pid_t pid) {
  const std::filesystem::path process = "/proc/" + std::to_string(pid);
  std::optional<double> total = cpu_seconds(stat_fields(process / "stat"));
  if (!total) return std::nullopt;
  // Less the threads under SCHED_IDLE (field 41, the policy): they take
  // only time no other thread wanted (tumbled --keep-cpus-awake).
  std::error_code error;
  for (const auto& task : std::filesystem::directory_iterator(process / "task", error)) {
    const std::vector<std::string> fields = stat_fields(task.path() / "stat");
    if (fields.size() < 41 - 2 || std::stoi(fields[41 - 3]) != SCHED_IDLE) continue;
    if (const std::optional<double> idle = cpu_seconds(fields)) *total -= *idle;
  }
  return total;
}

double cpu_percent(double cpu_seconds, double wall_seconds) {
  return wall_seconds > 0 ? 100 * cpu_seconds / wall_seconds : 0;
}

}  // namespace tumble::bench
