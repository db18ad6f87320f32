#include "nats/stream_spec.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

namespace tumble::nats {
namespace {

std::optional<std::string> check_name(std::string_view name, std::string_view what, std::string_view kind,
                                      std::size_t limit) {
  const bool fits = !name.empty() && name.size() <= limit;
  const bool plain = std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
  });
  if (fits && plain) return std::nullopt;
  return std::string(what) + ": " + std::string(kind) + " '" + std::string(name.substr(0, 80)) + "' must be 1 to " +
         std::to_string(limit) + " characters of A-Z a-z 0-9 _ - (no dot, no * or >: it is one token of a subject)";
}

}  // namespace

std::optional<std::string> check_world_name(std::string_view name, std::string_view what) {
  return check_name(name, what, "world name", kMaxWorldNameBytes);
}

std::optional<std::string> check_bucket_name(std::string_view name) {
  return check_name(name, "--nats-bucket", "bucket name", kMaxWorldNameBytes);
}

std::optional<std::string> check_stream_name(std::string_view name, std::string_view what) {
  return check_name(name, what, "stream name", kMaxStreamNameBytes);
}

std::variant<StreamSpec, std::string> parse_stream_spec(std::string_view text) {
  const std::string quoted = "--nats-stream '" + std::string(text.substr(0, 120)) + "': ";
  const std::string form = " (expected NAME=ENCODING@HZ[:fields], e.g. d30=delta@30:all)";
  const std::size_t equals = text.find('=');
  const std::size_t at = text.find('@');
  if (equals == std::string_view::npos || at == std::string_view::npos || at < equals) {
    return quoted + "does not parse" + form;
  }
  StreamSpec spec;
  spec.name = std::string(text.substr(0, equals));
  if (auto problem = check_stream_name(spec.name)) return *problem;
  const std::string_view encoding = text.substr(equals + 1, at - equals - 1);
  if (encoding == "full") {
    spec.encoding = tumble::v1::POSE_ENCODING_FULL;
  } else if (encoding == "quantized") {
    spec.encoding = tumble::v1::POSE_ENCODING_QUANTIZED;
  } else if (encoding == "delta") {
    spec.encoding = tumble::v1::POSE_ENCODING_DELTA;
  } else {
    return quoted + "encoding '" + std::string(encoding) + "' is not full, quantized or delta";
  }
  std::string_view rest = text.substr(at + 1);
  const std::size_t colon = rest.find(':');
  const std::string_view rate = rest.substr(0, colon);
  double hz = 0;
  const auto [end, error] = std::from_chars(rate.data(), rate.data() + rate.size(), hz);
  if (rate.empty() || error != std::errc() || end != rate.data() + rate.size() || !std::isfinite(hz) || hz <= 0 ||
      hz > 10000) {
    return quoted + "rate '" + std::string(rate) + "' must be a number of Hz above 0 and at most 10000";
  }
  spec.rate_hz = hz;
  if (colon != std::string_view::npos) {
    std::string_view fields = rest.substr(colon + 1);
    constexpr std::string_view kWithJoints = ",joints";
    if (fields == "joints") {
      spec.joints = true;
      fields = "pose";
    } else if (fields.ends_with(kWithJoints)) {
      spec.joints = true;
      fields.remove_suffix(kWithJoints.size());
    }
    if (fields == "all") {
      spec.velocities = true;
    } else if (fields != "pose") {
      return quoted + "fields '" + std::string(rest.substr(colon + 1)) +
             "' are not pose or all, with ,joints or without, nor joints";
    }
  }
  return spec;
}

std::string poses_subject(std::string_view world, std::string_view stream) {
  return "tumble.v1." + std::string(world) + ".poses." + std::string(stream);
}

std::string key_subject(std::string_view world, std::string_view stream) {
  return "tumble.v1." + std::string(world) + ".key." + std::string(stream);
}

std::string events_subject(std::string_view world) { return "tumble.v1." + std::string(world) + ".events"; }

std::string rpc_subject(std::string_view world) { return "tumble.v1." + std::string(world) + ".rpc"; }

std::string query_subject(std::string_view world) { return "tumble.v1." + std::string(world) + ".query"; }

std::string rpc_queue_group(std::string_view world) { return "tumble." + std::string(world) + ".rpc"; }

}  // namespace tumble::nats
