#include "tumble_client/nats_connection.h"

#include <nats/nats.h>

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "tumble_client/deadline.h"
#include "tumble_client/nats_subjects.h"
#include "tumble_client/sequence_gate.h"

namespace tumble::client {
namespace {

using Clock = std::chrono::steady_clock;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// The subscription id frames and events carry once handed over.
constexpr std::uint32_t kSubscriptionId = 1;

// Frames queued while the caller does not read; past this the oldest frame
// is dropped (a DELTA reader then waits for a key frame), events are kept.
constexpr std::size_t kMaxQueuedFrames = 256;

// What arrived on one of the connection's subscriptions.
struct Delivery {
  enum class Source { frame, event, key_reply, reply };
  Source source = Source::reply;
  std::string token;  // the last token of an inbox subject: which request it answers
  std::string data;
  bool no_responders = false;  // NATS's answer to a request nobody listens for
};

// Everything nats.c's threads hand to the caller's thread.
struct Mailbox {
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<Delivery> stream;   // frames, key replies and events, in arrival order
  std::deque<Delivery> replies;  // answers to requests, until taken
  std::size_t queued_frames = 0;
  std::vector<std::string> violations;  // NATS's permission errors, in order
  bool closed = false;

  void push(Delivery delivery) {
    {
      const std::lock_guard lock(mutex);
      if (delivery.source == Delivery::Source::reply) {
        replies.push_back(std::move(delivery));
      } else {
        if (delivery.source != Delivery::Source::event && ++queued_frames > kMaxQueuedFrames) {
          const auto oldest = std::find_if(stream.begin(), stream.end(),
                                           [](const Delivery& d) { return d.source != Delivery::Source::event; });
          stream.erase(oldest);
          --queued_frames;
        }
        stream.push_back(std::move(delivery));
      }
    }
    changed.notify_all();
  }
};

// nats.c may call back after a connection is destroyed, so callbacks find
// their mailbox by a number in this registry instead of holding a pointer.
// Leaked on purpose: nats.c's threads may outlive static destructors.
struct Registry {
  std::mutex mutex;
  std::uintptr_t next = 1;
  std::unordered_map<std::uintptr_t, std::shared_ptr<Mailbox>> mailboxes;
};

Registry& registry() {
  static Registry* const instance = new Registry;
  return *instance;
}

std::shared_ptr<Mailbox> mailbox_of(void* closure) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  const auto it = r.mailboxes.find(reinterpret_cast<std::uintptr_t>(closure));
  return it == r.mailboxes.end() ? nullptr : it->second;
}

// Copies a message out of nats.c and frees it.
Delivery take(natsMsg* msg, Delivery::Source source) {
  Delivery delivery;
  delivery.source = source;
  delivery.data.assign(natsMsg_GetData(msg), static_cast<std::size_t>(natsMsg_GetDataLength(msg)));
  delivery.no_responders = natsMsg_IsNoResponders(msg);
  const std::string_view subject = natsMsg_GetSubject(msg);
  delivery.token = std::string(subject.substr(subject.rfind('.') + 1));
  natsMsg_Destroy(msg);
  return delivery;
}

void on_frame(natsConnection*, natsSubscription*, natsMsg* msg, void* closure) {
  Delivery delivery = take(msg, Delivery::Source::frame);
  if (auto mailbox = mailbox_of(closure)) mailbox->push(std::move(delivery));
}

void on_event(natsConnection*, natsSubscription*, natsMsg* msg, void* closure) {
  Delivery delivery = take(msg, Delivery::Source::event);
  if (auto mailbox = mailbox_of(closure)) mailbox->push(std::move(delivery));
}

// Replies come to one inbox; a token starting with 'k' answers a key frame
// request and joins the stream, in order with the frames.
void on_inbox(natsConnection*, natsSubscription*, natsMsg* msg, void* closure) {
  Delivery delivery = take(msg, Delivery::Source::reply);
  if (!delivery.token.empty() && delivery.token.front() == 'k') delivery.source = Delivery::Source::key_reply;
  if (auto mailbox = mailbox_of(closure)) mailbox->push(std::move(delivery));
}

void on_error(natsConnection* nc, natsSubscription*, natsStatus status, void* closure) {
  if (status != NATS_NOT_PERMITTED) return;
  const char* text = nullptr;
  natsConnection_GetLastError(nc, &text);
  std::string what = text != nullptr ? text : "Permissions Violation";
  if (auto mailbox = mailbox_of(closure)) {
    {
      const std::lock_guard lock(mailbox->mutex);
      mailbox->violations.push_back(std::move(what));
    }
    mailbox->changed.notify_all();
  }
}

void on_closed(natsConnection*, void* closure) {
  if (auto mailbox = mailbox_of(closure)) {
    {
      const std::lock_guard lock(mailbox->mutex);
      mailbox->closed = true;
    }
    mailbox->changed.notify_all();
  }
}

std::int64_t milliseconds(Timeout timeout) {
  if (timeout <= Timeout::zero()) return 1;
  if (timeout >= std::chrono::hours(24 * 365)) return std::int64_t{1} << 40;
  return std::max<std::int64_t>(1, std::chrono::ceil<std::chrono::milliseconds>(timeout).count());
}

// nats.c's own words for the last failure of this thread, without the
// "(conn.c:2088): " of where in nats.c it was found.
std::string last_error(natsStatus status) {
  const char* text = nats_GetLastError(nullptr);
  std::string out = text != nullptr && *text != '\0' ? text : natsStatus_GetText(status);
  if (!out.empty() && out.front() == '(') {
    const std::size_t end = out.find("): ");
    if (end != std::string::npos) out.erase(0, end + 3);
  }
  return out;
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : ",") + without_credentials(item);
  return out;
}

std::string seconds_text(Timeout timeout) {
  std::ostringstream text;
  text << std::chrono::duration<double>(timeout).count();
  return text.str();
}

// "not permitted: ..." from NATS's "Permissions Violation for Publish to "x"".
Failure not_permitted(const std::string& violation) {
  return Failure{FailureKind::server, "not permitted: the NATS server refused this user: " + violation,
                 tumble::v1::PERMISSION_DENIED};
}

}  // namespace

std::string without_credentials(const std::string& url) {
  const std::size_t scheme = url.find("://");
  const std::size_t start = scheme == std::string::npos ? 0 : scheme + 3;
  const std::size_t at = url.find('@', start);
  if (at == std::string::npos || url.find('/', start) < at) return url;
  return url.substr(0, start) + url.substr(at + 1);
}

struct NatsConnection::State {
  ~State() {
    {
      Registry& r = registry();
      const std::lock_guard lock(r.mutex);
      r.mailboxes.erase(id);
    }
    for (natsSubscription* sub : subscriptions) natsSubscription_Destroy(sub);
    natsConnection_Destroy(connection);
  }

  // Waits until `ready` holds (checked under the mailbox's lock), the
  // deadline passes (false), or the connection closes or NATS reports a
  // permission error after `violations_seen` (true: the caller looks).
  template <typename Ready>
  bool wait(std::unique_lock<std::mutex>& lock, const std::optional<Clock::time_point>& deadline, Ready ready) {
    const auto stop = [&] { return ready() || mailbox->closed || mailbox->violations.size() > violations_seen; };
    if (!deadline) {
      mailbox->changed.wait(lock, stop);
      return true;
    }
    return mailbox->changed.wait_until(lock, *deadline, stop);
  }

  // The failure a wait that stopped for anything but its own reason stands for; none otherwise.
  std::optional<Failure> interruption() {
    if (mailbox->violations.size() > violations_seen) {
      const std::string violation = mailbox->violations[violations_seen];
      violations_seen = mailbox->violations.size();
      return not_permitted(violation);
    }
    if (mailbox->closed) return Failure{FailureKind::closed, "the NATS connection closed"};
    return std::nullopt;
  }

  // Publishes `payload` to `subject` asking for replies on inbox.<token>.
  std::optional<Failure> publish_request(const std::string& subject, const std::string& token,
                                         const std::string& payload) {
    const std::string reply = inbox + "." + token;
    const natsStatus status = natsConnection_PublishRequest(connection, subject.c_str(), reply.c_str(), payload.data(),
                                                            static_cast<int>(payload.size()));
    if (status == NATS_OK) return std::nullopt;
    if (status == NATS_CONNECTION_CLOSED) return Failure{FailureKind::closed, "the NATS connection closed"};
    return Failure{FailureKind::closed, "cannot publish to " + subject + ": " + last_error(status)};
  }

  // Asks the stream for its latest frame as a key frame; the reply joins the stream.
  void request_key_frame() {
    if (publish_request(key_subject(options.world, stream.name()), "k" + std::to_string(next_token++), "")) {
      gate.key_request_failed();
    }
  }

  std::uintptr_t id = 0;  // the mailbox's number in the registry
  std::shared_ptr<Mailbox> mailbox = std::make_shared<Mailbox>();
  NatsOptions options;
  natsConnection* connection = nullptr;
  std::vector<natsSubscription*> subscriptions;
  std::string inbox;  // this connection's reply prefix; inbox.* is subscribed
  std::uint64_t next_request_id = 1;
  std::uint64_t next_token = 1;
  std::size_t violations_seen = 0;
  tumble::v1::NatsStreamInfo stream;                    // the stream subscribe() chose
  std::vector<tumble::v1::WorldEventKind> event_kinds;  // the kinds subscribe() asked for
  SequenceGate gate;
};

Result<NatsConnection> NatsConnection::connect(const NatsOptions& options, Timeout timeout) {
  if (options.servers.empty()) return Failure{FailureKind::invalid_argument, "no NATS server given"};
  auto state = std::make_unique<State>();
  state->options = options;
  {
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    state->id = r.next++;
    r.mailboxes.emplace(state->id, state->mailbox);
  }
  void* const closure = reinterpret_cast<void*>(state->id);
  const std::string where = joined(options.servers);

  natsOptions* nats_options = nullptr;
  if (natsOptions_Create(&nats_options) != NATS_OK) {
    return Failure{FailureKind::connect, "cannot set up the NATS client: " + last_error(NATS_NO_MEMORY)};
  }
  std::vector<const char*> urls;
  for (const std::string& url : options.servers) urls.push_back(url.c_str());
  natsStatus status = natsOptions_SetServers(nats_options, urls.data(), static_cast<int>(urls.size()));
  if (status != NATS_OK) {
    natsOptions_Destroy(nats_options);
    return Failure{FailureKind::invalid_argument, "bad NATS URL in '" + where + "': " + last_error(status)};
  }
  natsOptions_SetTimeout(nats_options, milliseconds(timeout));
  natsOptions_SetNoRandomize(nats_options, true);
  if (!options.client_name.empty()) natsOptions_SetName(nats_options, options.client_name.c_str());
  natsOptions_SetErrorHandler(nats_options, on_error, closure);
  natsOptions_SetClosedCB(nats_options, on_closed, closure);
  if (!options.credentials_file.empty()) {
    status = natsOptions_SetUserCredentialsFromFiles(nats_options, options.credentials_file.c_str(), nullptr);
    if (status != NATS_OK) {
      natsOptions_Destroy(nats_options);
      return Failure{FailureKind::invalid_argument,
                     "cannot use the credentials file '" + options.credentials_file + "': " + last_error(status)};
    }
  }
  status = natsConnection_Connect(&state->connection, nats_options);
  natsOptions_Destroy(nats_options);
  if (status != NATS_OK) {
    const std::string why = last_error(status);
    if (status == NATS_CONNECTION_AUTH_FAILED || status == NATS_NOT_PERMITTED) {
      return Failure{FailureKind::server, "NATS at " + where + " refused the user or credentials: " + why,
                     tumble::v1::UNAUTHENTICATED};
    }
    if (status == NATS_TIMEOUT) {
      return Failure{FailureKind::timeout,
                     "timed out after " + seconds_text(timeout) + " s connecting to NATS at " + where + ": " + why};
    }
    if (!options.credentials_file.empty() && why.find(options.credentials_file) != std::string::npos) {
      return Failure{FailureKind::invalid_argument,
                     "cannot use the credentials file '" + options.credentials_file + "': " + why};
    }
    return Failure{FailureKind::connect, "cannot connect to NATS at " + where + ": " + why};
  }

  natsInbox* inbox = nullptr;
  status = natsInbox_Create(&inbox);
  if (status == NATS_OK) {
    state->inbox = inbox;
    natsInbox_Destroy(inbox);
    natsSubscription* sub = nullptr;
    status = natsConnection_Subscribe(&sub, state->connection, (state->inbox + ".*").c_str(), on_inbox, closure);
    if (status == NATS_OK) state->subscriptions.push_back(sub);
  }
  if (status != NATS_OK)
    return Failure{FailureKind::connect, "cannot subscribe to a NATS inbox: " + last_error(status)};
  return NatsConnection(std::move(state));
}

NatsConnection::NatsConnection(std::unique_ptr<State> state) : state_(std::move(state)) {}
NatsConnection::NatsConnection(NatsConnection&& other) noexcept = default;
NatsConnection& NatsConnection::operator=(NatsConnection&& other) noexcept = default;
NatsConnection::~NatsConnection() = default;

std::string NatsConnection::describe() const { return "world '" + state_->options.world + "' over NATS"; }

std::string NatsConnection::connected_url() const {
  char url[512] = {};
  if (natsConnection_GetConnectedUrl(state_->connection, url, sizeof url) != NATS_OK) return {};
  return url;
}

Result<ServerMessage> NatsConnection::request(ClientMessage message, Timeout timeout) {
  State& state = *state_;
  if (state.options.world.empty()) return Failure{FailureKind::invalid_argument, "no world given to send requests to"};
  const std::uint64_t id = state.next_request_id++;
  message.set_request_id(id);
  const std::string name = kind_name(message);
  // Reads go where any user may send them, so an observer lists bodies and stats too.
  const bool read_only =
      message.has_list_bodies() || message.has_list_joints() || message.has_get_stats() || message.has_hello();
  const std::string subject = read_only ? query_subject(state.options.world) : rpc_subject(state.options.world);
  const std::string token = "r" + std::to_string(id);
  const auto deadline = Deadline::after(timeout).at;
  if (auto failure = state.publish_request(subject, token, message.SerializeAsString())) return *failure;

  std::unique_lock lock(state.mailbox->mutex);
  std::deque<Delivery>& replies = state.mailbox->replies;
  const auto mine = [&] {
    return std::find_if(replies.begin(), replies.end(), [&](const Delivery& d) { return d.token == token; });
  };
  const bool stopped = state.wait(lock, deadline, [&] { return mine() != replies.end(); });
  const auto found = mine();
  if (found == replies.end()) {
    if (stopped) {
      if (auto failure = state.interruption()) return *failure;
    }
    return Failure{FailureKind::timeout, "timed out after " + seconds_text(timeout) + " s waiting for the reply to " +
                                             name + " on " + subject};
  }
  const Delivery reply = std::move(*found);
  replies.erase(found);
  lock.unlock();

  if (reply.no_responders) {
    return Failure{FailureKind::connect,
                   "no server serves world '" + state.options.world + "': nothing answers on " + subject};
  }
  ServerMessage answer;
  if (!answer.ParseFromString(reply.data)) {
    return Failure{FailureKind::protocol, "the reply of " + std::to_string(reply.data.size()) + " bytes on " + subject +
                                              " is not a tumble.v1.ServerMessage"};
  }
  if (answer.has_error()) return server_failure(answer.error());
  if (echoed_request_id(answer) != id) {
    return Failure{FailureKind::protocol, "the reply to " + name + " on " + subject + " echoes request id " +
                                              std::to_string(echoed_request_id(answer)) + ", not " +
                                              std::to_string(id)};
  }
  const ServerMessage::KindCase expected = expected_reply(message.kind_case());
  if (expected != ServerMessage::KIND_NOT_SET && answer.kind_case() != expected) {
    return Failure{FailureKind::protocol, "the server answered " + name + " with " + kind_name(answer)};
  }
  return answer;
}

Result<WorldInfos> NatsConnection::find_worlds(Timeout quiet, Timeout timeout) {
  State& state = *state_;
  const std::string token = "w" + std::to_string(state.next_token++);
  const auto deadline = Deadline::after(timeout).at;
  if (auto failure = state.publish_request(std::string(kWorldsSubject), token, "")) return *failure;

  WorldInfos worlds;
  std::unique_lock lock(state.mailbox->mutex);
  std::deque<Delivery>& replies = state.mailbox->replies;
  const auto mine = [&] {
    return std::find_if(replies.begin(), replies.end(), [&](const Delivery& d) { return d.token == token; });
  };
  for (;;) {
    // Each reply opens another quiet period, never past the deadline.
    auto until = Deadline::after(quiet).at;
    if (deadline && until && *deadline < *until) until = deadline;
    if (!state.wait(lock, until, [&] { return mine() != replies.end(); })) break;
    const auto found = mine();
    if (found == replies.end()) {
      if (auto failure = state.interruption()) return *failure;
      break;
    }
    const Delivery reply = std::move(*found);
    replies.erase(found);
    if (reply.no_responders) break;  // no server at all
    tumble::v1::WorldInfo info;
    if (!info.ParseFromString(reply.data)) {
      return Failure{FailureKind::protocol, "a reply of " + std::to_string(reply.data.size()) + " bytes on " +
                                                std::string(kWorldsSubject) + " is not a tumble.v1.WorldInfo"};
    }
    worlds.push_back(std::move(info));
  }
  std::sort(worlds.begin(), worlds.end(), [](const tumble::v1::WorldInfo& a, const tumble::v1::WorldInfo& b) {
    return std::tie(a.world(), a.server_id()) < std::tie(b.world(), b.server_id());
  });
  return worlds;
}

Result<tumble::v1::Subscribed> NatsConnection::subscribe(const tumble::v1::Subscribe& subscribe, Timeout timeout) {
  State& state = *state_;
  const std::string& world = state.options.world;
  if (world.empty()) return Failure{FailureKind::invalid_argument, "no world given to read frames of"};
  if (!state.stream.name().empty()) {
    return Failure{FailureKind::invalid_argument, "this connection already reads stream '" + state.stream.name() + "'"};
  }
  auto worlds = find_worlds(kWorldsQuietPeriod, timeout);
  if (!worlds) return worlds.failure();
  // The leader's answer: a standby's (--nats-state) names no streams.
  const auto info = std::find_if(worlds->begin(), worlds->end(),
                                 [&](const tumble::v1::WorldInfo& w) { return w.world() == world && !w.standby(); });
  if (info == worlds->end()) {
    const bool standbys =
        std::any_of(worlds->begin(), worlds->end(), [&](const tumble::v1::WorldInfo& w) { return w.world() == world; });
    return Failure{FailureKind::connect,
                   standbys ? "world '" + world +
                                  "' has no leader now, only standbys (a "
                                  "takeover under way?)"
                            : "no server answered for world '" + world + "' on " + std::string(kWorldsSubject)};
  }
  if (info->streams().empty()) {
    return Failure{FailureKind::invalid_argument, "world '" + world + "' publishes no pose stream"};
  }
  const auto chosen = std::find_if(info->streams().begin(), info->streams().end(), [&](const auto& s) {
    return state.options.stream.empty() || s.name() == state.options.stream;
  });
  if (chosen == info->streams().end()) {
    std::string names;
    for (const auto& s : info->streams()) names += (names.empty() ? "" : ", ") + s.name();
    return Failure{FailureKind::invalid_argument,
                   "world '" + world + "' has no stream '" + state.options.stream + "'; it has " + names};
  }
  state.stream = *chosen;

  void* const closure = reinterpret_cast<void*>(state.id);
  const auto add = [&](const std::string& subject, natsMsgHandler handler) -> std::optional<Failure> {
    natsSubscription* sub = nullptr;
    const natsStatus status = natsConnection_Subscribe(&sub, state.connection, subject.c_str(), handler, closure);
    if (status != NATS_OK)
      return Failure{FailureKind::closed, "cannot subscribe to " + subject + ": " + last_error(status)};
    state.subscriptions.push_back(sub);
    return std::nullopt;
  };
  if (auto failure = add(poses_subject(world, state.stream.name()), on_frame)) return *failure;
  for (const int kind : subscribe.events()) state.event_kinds.push_back(static_cast<tumble::v1::WorldEventKind>(kind));
  if (!state.event_kinds.empty()) {
    if (auto failure = add(events_subject(world), on_event)) return *failure;
  }
  // The server has the subscriptions once it answers the flush's ping;
  // a refused one is reported before that answer.
  const natsStatus flushed = natsConnection_FlushTimeout(state.connection, milliseconds(timeout));
  if (flushed != NATS_OK) {
    return Failure{FailureKind::timeout, "NATS did not confirm the subscriptions: " + last_error(flushed)};
  }
  state.request_key_frame();

  tumble::v1::Subscribed subscribed;
  subscribed.set_subscription_id(kSubscriptionId);
  subscribed.set_rate_hz(state.stream.rate_hz());
  subscribed.set_encoding(state.stream.encoding());
  if (state.stream.rate_hz() > 0) {
    subscribed.set_period_ticks(
        static_cast<std::uint32_t>(std::max(1.0, info->tick_rate_hz() / state.stream.rate_hz() + 0.5)));
  }
  return subscribed;
}

Result<ServerMessage> NatsConnection::next_message(Timeout timeout) {
  State& state = *state_;
  const auto deadline = Deadline::after(timeout).at;
  for (;;) {
    std::unique_lock lock(state.mailbox->mutex);
    std::deque<Delivery>& stream = state.mailbox->stream;
    if (!state.wait(lock, deadline, [&] { return !stream.empty(); })) {
      return Failure{FailureKind::timeout, "no frame or event within " + seconds_text(timeout) + " s"};
    }
    if (stream.empty()) {
      if (auto failure = state.interruption()) return *failure;
      continue;
    }
    Delivery delivery = std::move(stream.front());
    stream.pop_front();
    if (delivery.source != Delivery::Source::event) --state.mailbox->queued_frames;
    lock.unlock();

    if (delivery.no_responders) {  // a key frame request nobody answered
      state.gate.key_request_failed();
      continue;
    }
    ServerMessage message;
    if (!message.ParseFromString(delivery.data)) {
      return Failure{FailureKind::protocol, "a message of " + std::to_string(delivery.data.size()) +
                                                " bytes on world '" + state.options.world +
                                                "' is not a tumble.v1.ServerMessage"};
    }
    if (delivery.source == Delivery::Source::event) {
      if (!message.has_world_event()) continue;
      const auto kind = message.world_event().kind();
      if (std::find(state.event_kinds.begin(), state.event_kinds.end(), kind) == state.event_kinds.end()) continue;
      message.mutable_world_event()->set_subscription_id(kSubscriptionId);
      return message;
    }
    if (!message.has_pose_frame()) {
      if (message.has_error()) return server_failure(message.error());
      continue;
    }
    const SequenceGate::Verdict verdict = delivery.source == Delivery::Source::key_reply
                                              ? state.gate.key_reply(message.pose_frame())
                                              : state.gate.published(message.pose_frame());
    if (verdict.request_key) state.request_key_frame();
    if (!verdict.show) continue;
    message.mutable_pose_frame()->set_subscription_id(kSubscriptionId);
    return message;
  }
}

void close_nats_library(Timeout timeout) {
  nats_CloseAndWait(std::chrono::duration_cast<std::chrono::milliseconds>(timeout).count());
}

}  // namespace tumble::client
