// Tokens and roles: who gets in, as what, and what an observer may ask.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "net/access.h"

namespace tumble::net {
namespace {

using tumble::v1::ClientMessage;

TEST(Access, WithoutTokensEveryoneIsAController) {
  const AccessTokens none;
  EXPECT_FALSE(none.required());
  EXPECT_EQ(authenticate(none, ""), tumble::v1::ROLE_CONTROLLER);
  EXPECT_EQ(authenticate(none, "anything"), tumble::v1::ROLE_CONTROLLER);
}

TEST(Access, TokensGrantTheirRoles) {
  const AccessTokens tokens{"control-me", "just-looking"};
  EXPECT_EQ(authenticate(tokens, "control-me"), tumble::v1::ROLE_CONTROLLER);
  EXPECT_EQ(authenticate(tokens, "just-looking"), tumble::v1::ROLE_OBSERVER);
}

TEST(Access, WrongOrMissingTokensAreRefused) {
  const AccessTokens tokens{"control-me", "just-looking"};
  EXPECT_EQ(authenticate(tokens, ""), std::nullopt);
  EXPECT_EQ(authenticate(tokens, "control-m"), std::nullopt);             // a prefix
  EXPECT_EQ(authenticate(tokens, "control-me!"), std::nullopt);           // longer
  EXPECT_EQ(authenticate(tokens, "Control-me"), std::nullopt);            // one byte off
  EXPECT_EQ(authenticate(tokens, "control-mecontrol-me"), std::nullopt);  // the token twice
  EXPECT_EQ(authenticate(tokens, std::string("control-me\0", 11)), std::nullopt);
}

TEST(Access, AnUnsetTokenMatchesNothing) {
  const AccessTokens controller_only{"secret", ""};
  EXPECT_TRUE(controller_only.required());
  EXPECT_EQ(authenticate(controller_only, ""), std::nullopt);
  EXPECT_EQ(authenticate(controller_only, "secret"), tumble::v1::ROLE_CONTROLLER);

  const AccessTokens observer_only{"", "look"};
  EXPECT_EQ(authenticate(observer_only, ""), std::nullopt);
  EXPECT_EQ(authenticate(observer_only, "look"), tumble::v1::ROLE_OBSERVER);
}

TEST(Access, ObserversMayOnlyRead) {
  EXPECT_TRUE(observer_may(ClientMessage::kListBodies));
  EXPECT_TRUE(observer_may(ClientMessage::kSubscribe));
  EXPECT_TRUE(observer_may(ClientMessage::kUnsubscribe));
  EXPECT_TRUE(observer_may(ClientMessage::kHello));
  EXPECT_TRUE(observer_may(ClientMessage::KIND_NOT_SET));
  EXPECT_FALSE(observer_may(ClientMessage::kApplyForce));
  EXPECT_FALSE(observer_may(ClientMessage::kApplyTorque));
  EXPECT_FALSE(observer_may(ClientMessage::kApplyImpulse));
}

TEST(Access, EveryRequestNotOnTheAllowlistIsDeniedToObservers) {
  // Walks every request the protocol has, so a request added later is
  // denied to observers unless it is put on the allowlist on purpose.
  const auto* oneof = ClientMessage::descriptor()->FindOneofByName("kind");
  ASSERT_NE(oneof, nullptr);
  std::set<std::string> allowed;
  for (int i = 0; i < oneof->field_count(); ++i) {
    const auto kind = static_cast<ClientMessage::KindCase>(oneof->field(i)->number());
    EXPECT_TRUE(role_may(tumble::v1::ROLE_CONTROLLER, kind)) << oneof->field(i)->name();
    EXPECT_EQ(role_may(tumble::v1::ROLE_OBSERVER, kind), observer_may(kind)) << oneof->field(i)->name();
    if (observer_may(kind)) allowed.insert(oneof->field(i)->name());
  }
  std::set<std::string> reads = {"hello",     "list_bodies", "list_joints",
                                 "subscribe", "unsubscribe", "key_frame_request"};
  if (oneof->containing_type()->FindFieldByName("get_stats") != nullptr) reads.insert("get_stats");
  EXPECT_EQ(allowed, reads);
}

TEST(Access, NoRoleMayDoNothing) {
  EXPECT_FALSE(role_may(tumble::v1::ROLE_UNSPECIFIED, ClientMessage::kListBodies));
  EXPECT_FALSE(role_may(tumble::v1::ROLE_UNSPECIFIED, ClientMessage::kApplyForce));
}

TEST(Access, DenialNamesTheRequest) {
  const std::string text = observer_denial(ClientMessage::kApplyForce);
  EXPECT_NE(text.find("ApplyForce"), std::string::npos) << text;
  EXPECT_NE(text.find("controller token"), std::string::npos) << text;
}

}  // namespace
}  // namespace tumble::net
