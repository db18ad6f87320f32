// NatsConnection: a world served into NATS, reached through a NATS server
// with the nats.c client.
//
// Requests go to tumble.v1.<world>.rpc (reads: Hello, ListBodies,
// ListJoints and GetStats, to tumble.v1.<world>.query) and are answered by whichever
// server of the world takes them; pose frames are read from one of the
// streams the world publishes (tumble.v1.<world>.poses.<stream>), world
// events from tumble.v1.<world>.events. The NATS user's permissions are the
// role: a request the user may not publish is refused by NATS, and fails
// here with kind server and code PERMISSION_DENIED.
//
// nats.c delivers on threads of its own; everything they bring is queued
// here and handed over by the calling thread, so the NatsConnection itself
// is used from one thread at a time like any Transport. nats.c reconnects
// by itself while the connection lives.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tumble/v1/world_info.pb.h"
#include "tumble_client/transport.h"

namespace tumble::client {

// How to reach a world over NATS.
struct NatsOptions {
  // NATS servers, e.g. "nats://127.0.0.1:4222"; a user and password or a
  // token go in the URL (nats://user:pass@host:port), tls:// asks for TLS.
  std::vector<std::string> servers;
  std::string world;             // the world to send requests to; may be empty for find_worlds() alone
  std::string stream;            // the stream subscribe() reads; empty: the first the world lists
  std::string credentials_file;  // a NATS .creds file (JWT and NKey seed); empty: none
  std::string client_name;       // the connection's name on the NATS server
};

// Discovery: every tumble server answering on tumble.v1.worlds, in order of
// world name, then server id.
using WorldInfos = std::vector<tumble::v1::WorldInfo>;

// After a request on tumble.v1.worlds, replies are collected until none has
// come for this long.
inline constexpr Timeout kWorldsQuietPeriod = std::chrono::milliseconds(250);

// `url` without the user, password or token it may carry:
// "nats://user:pass@host:4222" becomes "nats://host:4222".
std::string without_credentials(const std::string& url);

class NatsConnection final : public Transport {
 public:
  // Connects to the first server of `options.servers` that answers (nats.c
  // tries them in turn). `timeout` bounds the attempt. Fails with kind
  // connect when none could be reached, server with UNAUTHENTICATED when
  // the NATS server refused the user, password, token or credentials,
  // invalid_argument when the credentials file cannot be read or a URL not
  // parsed, timeout.
  static Result<NatsConnection> connect(const NatsOptions& options, Timeout timeout);

  NatsConnection(NatsConnection&& other) noexcept;
  NatsConnection& operator=(NatsConnection&& other) noexcept;
  NatsConnection(const NatsConnection&) = delete;
  NatsConnection& operator=(const NatsConnection&) = delete;
  // Unsubscribes and closes; what was queued is discarded.
  ~NatsConnection() override;

  // "world 'demo' over NATS".
  std::string describe() const override;

  // One request on the world's .rpc subject (.query for a read), the reply
  // checked as over TCP.
  // Besides Transport::request()'s failures: kind connect when no server of
  // the world listens (NATS's "no responders"), server PERMISSION_DENIED
  // when the NATS user may not publish there, invalid_argument without a
  // world.
  Result<tumble::v1::ServerMessage> request(tumble::v1::ClientMessage message, Timeout timeout) override;

  // Reads the chosen stream (see NatsOptions::stream; the world's
  // WorldInfo, asked on tumble.v1.worlds, names its streams) and, when
  // `subscribe` asks for any event kind, the world's events of those kinds.
  // The stream's rate, encoding and fields apply; the request's are not
  // used, and neither are its bodies (a stream covers every body). A key
  // frame is asked for at once, so the current state comes without waiting
  // for the stream's next one. The reply gives subscription id 1, the
  // stream's rate and encoding. Fails with kind invalid_argument when the
  // world has no such stream, connect when no server answers for the world.
  Result<tumble::v1::Subscribed> subscribe(const tumble::v1::Subscribe& subscribe, Timeout timeout) override;

  // The next frame of the stream that may be shown (a SequenceGate decides:
  // after a gap in a DELTA stream, nothing until a key frame, which is
  // asked for at once), or the next event, in the order they arrived. A
  // frame and an event of the same tick travel on different subjects, so
  // their order is not kept. Fails with kind timeout when nothing came in
  // time, closed when the NATS connection closed for good, server
  // PERMISSION_DENIED when NATS refused a subscription.
  Result<tumble::v1::ServerMessage> next_message(Timeout timeout) override;

  // Asks tumble.v1.worlds and collects the replies until none came for
  // `quiet`, or `timeout` passed. No server answering is an empty list, not
  // a failure. Fails with kind protocol on a reply that is not a WorldInfo,
  // server PERMISSION_DENIED when the user may not ask.
  Result<WorldInfos> find_worlds(Timeout quiet, Timeout timeout);

  // The NATS server connected to now, without credentials.
  std::string connected_url() const;

 private:
  struct State;
  explicit NatsConnection(std::unique_ptr<State> state);

  std::unique_ptr<State> state_;  // null only in a moved-from NatsConnection
};

// Waits for nats.c's own threads to finish, up to `timeout`, so that none of
// them still runs (in OpenSSL, say) while the process exits. Call once, from
// main, after every NatsConnection is gone; none may be made afterwards.
void close_nats_library(Timeout timeout = std::chrono::seconds(2));

}  // namespace tumble::client
