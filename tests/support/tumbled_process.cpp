#include "tumbled_process.h"

#include <fstream>
#include <thread>

namespace tumble::test {

TumbledProcess::TumbledProcess(const std::string& scene_json, const std::vector<std::string>& extra_args,
                               std::uint16_t port)
    : dir_(make_temp_dir()), log_path_(dir_ + "/tumbled.log") {
  const std::string scene_path = dir_ + "/scene.json";
  const std::string port_path = dir_ + "/port";
  std::ofstream(scene_path) << scene_json;
  std::vector<std::string> argv = {
      tumbled_path(), "--scene", scene_path, "--listen", "127.0.0.1:" + std::to_string(port), "--port-file", port_path};
  argv.insert(argv.end(), extra_args.begin(), extra_args.end());
  process_ = std::make_unique<ChildProcess>(argv, log_path_);
  // Generous: a loaded machine or a sanitizer build can take seconds to start.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline && process_->running()) {
    const std::string text = read_file(port_path);
    if (!text.empty()) {
      port_ = static_cast<std::uint16_t>(std::stoul(text));
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

CommandResult TumbledProcess::cli(const std::vector<std::string>& args, std::chrono::milliseconds timeout) const {
  std::vector<std::string> argv = {tumble_cli_path(), "--server", server()};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command(argv, timeout);
}

}  // namespace tumble::test
