#include "nats_test_client.h"

#include <sstream>
#include <thread>

namespace tumble::test {

NatsCollector::~NatsCollector() {
  release();
  if (subscription_) {
    // on_message may be running on the subscription's thread: this
    // collector must outlive it, so wait for nats.c's word that it is done.
    if (natsSubscription_Unsubscribe(subscription_) == NATS_OK) {
      std::unique_lock lock(mutex_);
      changed_.wait_for(lock, std::chrono::seconds(10), [this] { return complete_; });
    }
    natsSubscription_Destroy(subscription_);
  }
}

void NatsCollector::on_complete(void* closure) {
  auto* self = static_cast<NatsCollector*>(closure);
  const std::lock_guard lock(self->mutex_);
  self->complete_ = true;
  self->changed_.notify_all();
}

void NatsCollector::on_message(natsConnection*, natsSubscription*, natsMsg* message, void* closure) {
  auto* self = static_cast<NatsCollector*>(closure);
  const char* reply = natsMsg_GetReply(message);
  NatsMessage copy{natsMsg_GetSubject(message),
                   std::string(natsMsg_GetData(message), static_cast<std::size_t>(natsMsg_GetDataLength(message))),
                   reply ? reply : ""};
  natsMsg_Destroy(message);
  std::unique_lock lock(self->mutex_);
  self->changed_.wait(lock, [self] { return !self->held_; });
  self->messages_.push_back(std::move(copy));
  self->changed_.notify_all();
}

bool NatsCollector::wait(const std::function<bool(const std::vector<NatsMessage>&)>& done,
                         std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return done(messages_); });
}

bool NatsCollector::wait_count(std::size_t count, std::chrono::milliseconds timeout) {
  return wait([count](const std::vector<NatsMessage>& messages) { return messages.size() >= count; }, timeout);
}

std::vector<NatsMessage> NatsCollector::messages() {
  std::lock_guard lock(mutex_);
  return messages_;
}

std::vector<NatsMessage> NatsCollector::take() {
  std::lock_guard lock(mutex_);
  std::vector<NatsMessage> out;
  out.swap(messages_);
  return out;
}

void NatsCollector::hold() {
  std::lock_guard lock(mutex_);
  held_ = true;
}

void NatsCollector::release() {
  std::lock_guard lock(mutex_);
  held_ = false;
  changed_.notify_all();
}

std::int64_t NatsCollector::dropped() {
  std::int64_t count = 0;
  if (subscription_) natsSubscription_GetDropped(subscription_, &count);
  return count;
}

NatsTestClient::NatsTestClient(const std::string& urls, std::chrono::milliseconds timeout) {
  std::vector<std::string> list;
  std::stringstream in(urls);
  for (std::string url; std::getline(in, url, ',');) list.push_back(url);
  std::vector<const char*> servers;
  for (const std::string& url : list) servers.push_back(url.c_str());
  natsOptions* options = nullptr;
  natsOptions_Create(&options);
  natsOptions_SetServers(options, servers.data(), static_cast<int>(servers.size()));
  natsOptions_SetMaxReconnect(options, -1);
  natsOptions_SetReconnectWait(options, 50);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  natsStatus status = NATS_OK;
  do {
    status = natsConnection_Connect(&connection_, options);
    if (status == NATS_OK) break;
    connection_ = nullptr;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  } while (std::chrono::steady_clock::now() < deadline);
  note(status);
  natsOptions_Destroy(options);
}

NatsTestClient::~NatsTestClient() {
  if (connection_) {
    natsConnection_Close(connection_);
    natsConnection_Destroy(connection_);
  }
}

void NatsTestClient::note(natsStatus status) {
  last_status_ = status;
  if (status == NATS_OK) {
    error_.clear();
    return;
  }
  const char* text = nullptr;
  if (connection_) natsConnection_GetLastError(connection_, &text);
  error_ = std::string(natsStatus_GetText(status)) + (text && *text ? std::string(": ") + text : std::string());
}

natsStatus NatsTestClient::publish(const std::string& subject, const std::string& data) {
  const natsStatus status =
      natsConnection_Publish(connection_, subject.c_str(), data.data(), static_cast<int>(data.size()));
  note(status);
  return status;
}

natsStatus NatsTestClient::flush(std::chrono::milliseconds timeout) {
  const natsStatus status = natsConnection_FlushTimeout(connection_, timeout.count());
  note(status);
  return status;
}

std::optional<std::string> NatsTestClient::request(const std::string& subject, const std::string& data,
                                                   std::chrono::milliseconds timeout) {
  natsMsg* reply = nullptr;
  const natsStatus status = natsConnection_Request(&reply, connection_, subject.c_str(), data.data(),
                                                   static_cast<int>(data.size()), timeout.count());
  note(status);
  if (status != NATS_OK) return std::nullopt;
  std::string out(natsMsg_GetData(reply), static_cast<std::size_t>(natsMsg_GetDataLength(reply)));
  natsMsg_Destroy(reply);
  return out;
}

std::vector<std::string> NatsTestClient::request_many(const std::string& subject, const std::string& data,
                                                      std::chrono::milliseconds quiet,
                                                      std::chrono::milliseconds timeout) {
  std::vector<std::string> replies;
  natsInbox* inbox = nullptr;
  natsInbox_Create(&inbox);
  natsSubscription* subscription = nullptr;
  natsStatus status = natsConnection_SubscribeSync(&subscription, connection_, inbox);
  if (status == NATS_OK) {
    status =
        natsConnection_PublishRequest(connection_, subject.c_str(), inbox, data.data(), static_cast<int>(data.size()));
  }
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (status == NATS_OK) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    natsMsg* reply = nullptr;
    if (natsSubscription_NextMsg(&reply, subscription, std::min(left, quiet).count()) != NATS_OK) break;
    replies.emplace_back(natsMsg_GetData(reply), static_cast<std::size_t>(natsMsg_GetDataLength(reply)));
    natsMsg_Destroy(reply);
  }
  note(status);
  natsSubscription_Destroy(subscription);
  natsInbox_Destroy(inbox);
  return replies;
}

std::unique_ptr<NatsCollector> NatsTestClient::subscribe(const std::string& subject, int pending_messages,
                                                         int pending_bytes) {
  std::unique_ptr<NatsCollector> collector(new NatsCollector());
  natsStatus status = natsConnection_Subscribe(&collector->subscription_, connection_, subject.c_str(),
                                               &NatsCollector::on_message, collector.get());
  if (status == NATS_OK) {
    status = natsSubscription_SetOnCompleteCB(collector->subscription_, &NatsCollector::on_complete, collector.get());
  }
  if (status == NATS_OK && pending_messages > 0) {
    status = natsSubscription_SetPendingLimits(collector->subscription_, pending_messages, pending_bytes);
  }
  if (status == NATS_OK) status = natsConnection_FlushTimeout(connection_, 5000);
  note(status);
  if (status != NATS_OK) return nullptr;
  return collector;
}

bool NatsTestClient::wait_for_interest(const std::string& subject, NatsCollector& collector,
                                       std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    publish(subject, "probe");
    if (collector.wait_count(1, std::chrono::milliseconds(50))) return true;
  }
  return false;
}

namespace {

// A JetStream context on `connection`; null (and `status` set) on failure.
jsCtx* jetstream_of(natsConnection* connection, natsStatus* status) {
  jsCtx* js = nullptr;
  *status = natsConnection_JetStream(&js, connection, nullptr);
  return *status == NATS_OK ? js : nullptr;
}

}  // namespace

std::optional<NatsTestClient::KvValue> NatsTestClient::kv_get(const std::string& bucket, const std::string& key) {
  natsStatus status = NATS_OK;
  jsCtx* js = jetstream_of(connection_, &status);
  kvStore* kv = nullptr;
  kvEntry* entry = nullptr;
  if (js != nullptr) status = js_KeyValue(&kv, js, bucket.c_str());
  if (status == NATS_OK) status = kvStore_Get(&entry, kv, key.c_str());
  note(status);
  std::optional<KvValue> value;
  if (status == NATS_OK) {
    value = KvValue{
        std::string(static_cast<const char*>(kvEntry_Value(entry)), static_cast<std::size_t>(kvEntry_ValueLen(entry))),
        kvEntry_Revision(entry)};
  }
  kvEntry_Destroy(entry);
  kvStore_Destroy(kv);
  jsCtx_Destroy(js);
  return value;
}

bool NatsTestClient::kv_put(const std::string& bucket, const std::string& key, const std::string& data) {
  natsStatus status = NATS_OK;
  jsCtx* js = jetstream_of(connection_, &status);
  kvStore* kv = nullptr;
  if (js != nullptr) status = js_KeyValue(&kv, js, bucket.c_str());
  if (status == NATS_OK) status = kvStore_Put(nullptr, kv, key.c_str(), data.data(), static_cast<int>(data.size()));
  note(status);
  kvStore_Destroy(kv);
  jsCtx_Destroy(js);
  return status == NATS_OK;
}

int NatsTestClient::kv_current_replicas(const std::string& bucket) {
  natsStatus status = NATS_OK;
  jsCtx* js = jetstream_of(connection_, &status);
  jsStreamInfo* info = nullptr;
  if (js != nullptr) status = js_GetStreamInfo(&info, js, ("KV_" + bucket).c_str(), nullptr, nullptr);
  note(status);
  int current = 0;
  if (status == NATS_OK && info->Cluster != nullptr) {
    if (info->Cluster->Leader != nullptr) ++current;
    for (int i = 0; i < info->Cluster->ReplicasLen; ++i) {
      if (info->Cluster->Replicas[i]->Current && !info->Cluster->Replicas[i]->Offline) ++current;
    }
  }
  jsStreamInfo_Destroy(info);
  jsCtx_Destroy(js);
  return current;
}

}  // namespace tumble::test
