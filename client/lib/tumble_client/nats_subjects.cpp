#include "tumble_client/nats_subjects.h"

namespace tumble::client {
namespace {

bool is_name_character(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

std::string name_problem(std::string_view what, std::string_view name, std::size_t max_length) {
  const std::string quoted = "'" + std::string(name) + "'";
  if (name.empty()) return "a " + std::string(what) + " name may not be empty";
  if (name.size() > max_length) {
    return "a " + std::string(what) + " name is at most " + std::to_string(max_length) + " characters, got " +
           std::to_string(name.size());
  }
  for (const char c : name) {
    if (!is_name_character(c)) {
      return "a " + std::string(what) + " name is made of A-Z a-z 0-9 _ - only (no dot, wildcard or space), got " +
             quoted;
    }
  }
  return {};
}

std::string world_prefix(std::string_view world) { return "tumble.v1." + std::string(world); }

}  // namespace

std::string world_name_problem(std::string_view name) { return name_problem("world", name, kMaxWorldNameLength); }

std::string stream_name_problem(std::string_view name) { return name_problem("stream", name, kMaxStreamNameLength); }

std::string rpc_subject(std::string_view world) { return world_prefix(world) + ".rpc"; }

std::string query_subject(std::string_view world) { return world_prefix(world) + ".query"; }

std::string events_subject(std::string_view world) { return world_prefix(world) + ".events"; }

std::string poses_subject(std::string_view world, std::string_view stream) {
  return world_prefix(world) + ".poses." + std::string(stream);
}

std::string key_subject(std::string_view world, std::string_view stream) {
  return world_prefix(world) + ".key." + std::string(stream);
}

}  // namespace tumble::client
