#include "process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <system_error>
#include <thread>

extern char** environ;

namespace tumble::test {
namespace {

std::vector<char*> c_argv(const std::vector<std::string>& argv) {
  std::vector<char*> out;
  for (const std::string& arg : argv) out.push_back(const_cast<char*>(arg.c_str()));
  out.push_back(nullptr);
  return out;
}

int decode_status(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

// The test's environment with `env` ("NAME=VALUE" each) put over it.
std::vector<std::string> merged_environment(const std::vector<std::string>& env) {
  std::vector<std::string> out;
  const auto name_of = [](const std::string& entry) { return entry.substr(0, entry.find('=')); };
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string inherited = *entry;
    bool replaced = false;
    for (const std::string& given : env) replaced = replaced || name_of(given) == name_of(inherited);
    if (!replaced) out.push_back(inherited);
  }
  out.insert(out.end(), env.begin(), env.end());
  return out;
}

pid_t spawn(const std::vector<std::string>& argv, const std::string& out_path, const std::string& err_path,
            const std::vector<std::string>& env = {}) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  pid_t pid = -1;
  auto args = c_argv(argv);
  const std::vector<std::string> environment = merged_environment(env);
  auto envp = c_argv(environment);
  if (posix_spawn(&pid, args[0], &actions, nullptr, args.data(), env.empty() ? environ : envp.data()) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

// The one directory under $TMPDIR (or /tmp) that holds every scratch
// directory of this test program, made on first use. After the last test
// it is removed with everything in it when every test passed, and kept,
// with its path printed, when one failed: the servers' logs are in it.
class ScratchRoot : public ::testing::Environment {
 public:
  const std::string& path() {
    if (path_.empty()) {
      const char* base = std::getenv("TMPDIR");
      std::string pattern = std::string(base ? base : "/tmp") + "/tumble-test-XXXXXX";
      if (::mkdtemp(pattern.data()) != nullptr) path_ = pattern;
    }
    return path_;
  }

  void TearDown() override {
    if (path_.empty()) return;
    if (!::testing::UnitTest::GetInstance()->Passed()) {
      std::cerr << "the failed run's files are kept in " << path_ << "\n";
      return;
    }
    // A child that outlives its test may still be writing: what it leaves
    // is not worth failing the run for.
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }

 private:
  std::string path_;
};

// gtest owns the environment and runs its TearDown after the last test.
ScratchRoot* const scratch_root = static_cast<ScratchRoot*>(::testing::AddGlobalTestEnvironment(new ScratchRoot));

}  // namespace

std::string make_temp_dir() {
  const std::string& root = scratch_root->path();
  if (root.empty()) return "/tmp";
  std::string pattern = root + "/XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) return "/tmp";
  return pattern;
}

std::string read_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

CommandResult run_command(const std::vector<std::string>& argv, std::chrono::milliseconds timeout) {
  const std::string dir = make_temp_dir();
  const std::string out_path = dir + "/out";
  const std::string err_path = dir + "/err";
  CommandResult result;
  const pid_t pid = spawn(argv, out_path, err_path);
  if (pid > 0) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    int status = 0;
    for (;;) {
      const pid_t done = ::waitpid(pid, &status, WNOHANG);
      if (done == pid) {
        result.exit_code = decode_status(status);
        break;
      }
      if (std::chrono::steady_clock::now() > deadline) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        result.exit_code = -1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  result.out = read_file(out_path);
  result.err = read_file(err_path);
  std::remove(out_path.c_str());
  std::remove(err_path.c_str());
  ::rmdir(dir.c_str());
  return result;
}

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& log_path,
                           const std::vector<std::string>& env)
    : ChildProcess(argv, log_path, log_path, env) {}

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& out_path,
                           const std::string& err_path, const std::vector<std::string>& env) {
  if (argv.empty() || out_path.empty() || err_path.empty()) return;
  pid_ = spawn(argv, out_path, err_path, env);
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && running()) {
    ::kill(pid_, SIGKILL);
    wait(std::chrono::seconds(10));
  }
}

void ChildProcess::signal(int signal_number) {
  if (pid_ > 0 && !exit_code_) ::kill(pid_, signal_number);
}

std::optional<int> ChildProcess::wait(std::chrono::milliseconds timeout) {
  if (exit_code_ || pid_ <= 0) return exit_code_;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      exit_code_ = decode_status(status);
      return exit_code_;
    }
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

bool ChildProcess::running() { return pid_ > 0 && !wait(std::chrono::milliseconds(0)); }

}  // namespace tumble::test
