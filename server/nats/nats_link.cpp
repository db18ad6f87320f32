#include "nats/nats_link.h"

#include <array>
#include <cstdlib>

namespace tumble::nats {
namespace {

constexpr std::int64_t kDefaultMaxPayload = std::int64_t{1} << 20;

sim::Status failed(const std::string& what, natsStatus status) { return nats_failure(what, status); }

}  // namespace

sim::Status nats_failure(const std::string& what, natsStatus status) {
  std::string text = natsStatus_GetText(status);
  std::string detail = nats_GetLastError(nullptr) != nullptr ? nats_GetLastError(nullptr) : "";
  // nats.c starts it with its source position, "(conn.c:733): ".
  if (detail.rfind('(', 0) == 0 && detail.find("): ") != std::string::npos) detail.erase(0, detail.find("): ") + 3);
  if (!detail.empty() && detail != text) text += " (" + detail + ")";
  return sim::Status::error(what + ": " + text);
}

std::string without_credentials(std::string_view url) {
  const std::size_t scheme = url.find("://");
  const std::size_t start = scheme == std::string_view::npos ? 0 : scheme + 3;
  const std::size_t at = url.find('@', start);
  if (at == std::string_view::npos) return std::string(url);
  return std::string(url.substr(0, start)) + std::string(url.substr(at + 1));
}

NatsLibraryScope::~NatsLibraryScope() { nats_CloseAndWait(2000); }

NatsLink::NatsLink(NatsLinkConfig config, spdlog::logger& log) : config_(std::move(config)), log_(log) {}

NatsLink::~NatsLink() {
  close();
  if (connection_) natsConnection_Destroy(connection_);
  for (auto& subscription : subscriptions_) natsSubscription_Destroy(subscription->handle);
  natsOptions_Destroy(options_);
}

void NatsLink::close() {
  if (connection_ && !closing_.exchange(true, std::memory_order_relaxed)) {
    natsConnection_Close(connection_);
    // nats.c calls on_closed later, on a thread of its own: this link must
    // outlive that call.
    // Likewise a subscription's handler may still be running on its
    // dispatcher thread: wait for nats.c to say each one has returned.
    std::unique_lock lock(closed_mutex_);
    closed_wakeup_.wait_for(lock, std::chrono::seconds(5),
                            [this] { return closed_ && subscriptions_completed_ == subscriptions_.size(); });
  }
}

sim::Status NatsLink::start() {
  natsStatus status = natsOptions_Create(&options_);
  if (status != NATS_OK) return failed("--nats", status);
  std::vector<const char*> servers;
  for (const std::string& url : config_.urls) servers.push_back(url.c_str());
  if ((status = natsOptions_SetServers(options_, servers.data(), static_cast<int>(servers.size()))) != NATS_OK) {
    return failed("--nats", status);
  }
  natsOptions_SetName(options_, config_.name.c_str());
  natsOptions_SetNoRandomize(options_, true);  // the first URL first, as given
  natsOptions_SetMaxReconnect(options_, -1);   // never give up
  natsOptions_SetReconnectWait(options_, 250);
  natsOptions_SetReconnectJitter(options_, 100, 1000);
  natsOptions_SetReconnectBufSize(options_, config_.reconnect_buffer_bytes);
  natsOptions_SetPingInterval(options_, 2000);  // a dead server is noticed within a few seconds
  natsOptions_SetMaxPingsOut(options_, 2);
  natsOptions_SetDisconnectedCB(options_, &NatsLink::on_disconnected, this);
  natsOptions_SetReconnectedCB(options_, &NatsLink::on_reconnected, this);
  natsOptions_SetClosedCB(options_, &NatsLink::on_closed, this);
  natsOptions_SetErrorHandler(options_, &NatsLink::on_error, this);
  for (const std::string& url : config_.urls) {
    if (url.rfind("tls://", 0) == 0) natsOptions_SetSecure(options_, true);
  }
  if (!config_.creds_file.empty()) {
    status = natsOptions_SetUserCredentialsFromFiles(options_, config_.creds_file.c_str(), nullptr);
    if (status != NATS_OK) return failed("--nats-creds " + config_.creds_file, status);
  }
  // One attempt first, so that a server that answers but refuses the
  // credentials is an error at start rather than a link retried forever.
  natsOptions_SetRetryOnFailedConnect(options_, false, nullptr, nullptr);
  status = natsConnection_Connect(&connection_, options_);
  if (status == NATS_OK) {
    on_connected(connection_, this);
    return {};
  }
  connection_ = nullptr;
  if (status == NATS_CONNECTION_AUTH_FAILED || status == NATS_NOT_PERMITTED) {
    return sim::Status::error(std::string(config_.creds_file.empty() ? "--nats" : "--nats-creds") +
                              ": the NATS server refused the user, password, token or credentials (" +
                              natsStatus_GetText(status) + ")");
  }
  if (status != NATS_NO_SERVER && status != NATS_TIMEOUT && status != NATS_IO_ERROR) return failed("--nats", status);
  natsOptions_SetRetryOnFailedConnect(options_, true, &NatsLink::on_connected, this);
  status = natsConnection_Connect(&connection_, options_);
  if (status == NATS_OK) {
    on_connected(connection_, this);
  } else if (status == NATS_NOT_YET_CONNECTED) {
    log_.warn("NATS link down: no server of {} reachable yet; retrying in the background", config_.urls.size());
  } else {
    connection_ = nullptr;
    return failed("--nats", status);
  }
  return {};
}

sim::Status NatsLink::subscribe(const std::string& subject, const std::string& queue_group,
                                std::function<void(NatsRequest)> handler) {
  auto subscription = std::make_unique<Subscription>();
  subscription->link = this;
  subscription->handler = std::move(handler);
  natsStatus status =
      queue_group.empty()
          ? natsConnection_Subscribe(&subscription->handle, connection_, subject.c_str(), &NatsLink::on_message,
                                     subscription.get())
          : natsConnection_QueueSubscribe(&subscription->handle, connection_, subject.c_str(), queue_group.c_str(),
                                          &NatsLink::on_message, subscription.get());
  if (status == NATS_OK) {
    status =
        natsSubscription_SetOnCompleteCB(subscription->handle, &NatsLink::on_subscription_complete, subscription.get());
    if (status != NATS_OK) natsSubscription_Destroy(subscription->handle);
  }
  if (status != NATS_OK) return failed("subscribing to " + subject, status);
  subscriptions_.push_back(std::move(subscription));
  return {};
}

NatsLink::Sent NatsLink::publish(const std::string& subject, std::string_view data) {
  if (!up_.load(std::memory_order_relaxed)) return Sent::down;
  if (static_cast<std::int64_t>(data.size()) > max_payload()) return Sent::too_large;
  const natsStatus status =
      natsConnection_Publish(connection_, subject.c_str(), data.data(), static_cast<int>(data.size()));
  if (status == NATS_OK) {
    messages_out_.fetch_add(1, std::memory_order_relaxed);
    bytes_out_.fetch_add(data.size(), std::memory_order_relaxed);
    return Sent::ok;
  }
  return status == NATS_MAX_PAYLOAD                                                 ? Sent::too_large
         : (status == NATS_INSUFFICIENT_BUFFER || status == NATS_CONNECTION_CLOSED) ? Sent::down
                                                                                    : Sent::failed;
}

bool NatsLink::connected() const { return up_.load(std::memory_order_relaxed); }

std::size_t NatsLink::known_servers() const {
  if (!connection_) return config_.urls.size();
  char** servers = nullptr;
  int count = 0;
  if (natsConnection_GetServers(connection_, &servers, &count) != NATS_OK) return config_.urls.size();
  for (int i = 0; i < count; ++i) std::free(servers[i]);
  std::free(static_cast<void*>(servers));
  return static_cast<std::size_t>(count);
}

std::int64_t NatsLink::max_payload() const {
  const std::int64_t payload = connection_ ? natsConnection_GetMaxPayload(connection_) : 0;
  return payload > 0 ? payload : kDefaultMaxPayload;
}

std::string NatsLink::server_url() const {
  if (!connection_ || !connected()) return "";
  std::array<char, 512> buffer{};
  if (natsConnection_GetConnectedUrl(connection_, buffer.data(), buffer.size()) != NATS_OK) return "";
  return without_credentials(buffer.data());
}

void NatsLink::fill(const std::string& world, tumble::v1::NatsLink* out) const {
  out->set_connected(connected());
  out->set_server_url(server_url());
  out->set_messages_out(messages_out_.load(std::memory_order_relaxed));
  out->set_bytes_out(bytes_out_.load(std::memory_order_relaxed));
  out->set_reconnects(reconnects_.load(std::memory_order_relaxed));
  out->set_requests_in(requests_in_.load(std::memory_order_relaxed));
  out->set_frames_dropped(frames_dropped_.load(std::memory_order_relaxed));
  out->set_world(world);
}

std::string NatsLink::last_error() const {
  const char* text = nullptr;
  const natsStatus status = connection_ ? natsConnection_GetLastError(connection_, &text) : NATS_OK;
  if (status == NATS_OK) return "";
  return std::string(natsStatus_GetText(status)) + (text && *text ? std::string(": ") + text : std::string());
}

void NatsLink::on_connected(natsConnection*, void* closure) {
  auto* self = static_cast<NatsLink*>(closure);
  self->up_.store(true, std::memory_order_relaxed);
  self->log_.info("NATS link up: connected to {}", self->server_url());
}

void NatsLink::on_disconnected(natsConnection*, void* closure) {
  auto* self = static_cast<NatsLink*>(closure);
  self->up_.store(false, std::memory_order_relaxed);
  if (self->closing_.load(std::memory_order_relaxed)) return;  // our own close, not a loss
  const std::string reason = self->last_error();
  self->log_.warn("NATS link down{}{}; reconnecting", reason.empty() ? "" : ": ", reason);
}

void NatsLink::on_reconnected(natsConnection*, void* closure) {
  auto* self = static_cast<NatsLink*>(closure);
  self->reconnects_.fetch_add(1, std::memory_order_relaxed);
  self->up_.store(true, std::memory_order_relaxed);
  self->log_.info("NATS link up: reconnected to {}", self->server_url());
}

void NatsLink::on_closed(natsConnection*, void* closure) {
  auto* self = static_cast<NatsLink*>(closure);
  self->up_.store(false, std::memory_order_relaxed);
  // Last: the destructor may free the link as soon as it sees this.
  const std::lock_guard lock(self->closed_mutex_);
  self->closed_ = true;
  self->closed_wakeup_.notify_all();
}

void NatsLink::on_error(natsConnection*, natsSubscription*, natsStatus status, void* closure) {
  auto* self = static_cast<NatsLink*>(closure);
  const std::string reason = self->last_error();
  // e.g. "Authorization Violation", a permissions violation, a slow consumer.
  self->log_.error("NATS: {}", reason.empty() ? natsStatus_GetText(status) : reason);
}

void NatsLink::on_message(natsConnection*, natsSubscription*, natsMsg* message, void* closure) {
  auto* subscription = static_cast<Subscription*>(closure);
  const char* reply = natsMsg_GetReply(message);
  NatsRequest request{natsMsg_GetSubject(message), reply ? reply : "",
                      std::string(natsMsg_GetData(message), static_cast<std::size_t>(natsMsg_GetDataLength(message)))};
  natsMsg_Destroy(message);
  subscription->handler(std::move(request));
}

void NatsLink::on_subscription_complete(void* closure) {
  NatsLink& link = *static_cast<Subscription*>(closure)->link;
  const std::lock_guard lock(link.closed_mutex_);
  ++link.subscriptions_completed_;
  link.closed_wakeup_.notify_all();
}

}  // namespace tumble::nats
