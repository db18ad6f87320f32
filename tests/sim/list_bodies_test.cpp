// ListBodies in pages: every body once, in id order, each page within the
// page size, whatever start_id and max_bodies ask for.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "sim/simulation.h"

namespace tumble::sim {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

constexpr int kBodyCount = 500;

class ListBodiesTest : public ::testing::Test {
 protected:
  // kBodyCount spheres named "body-<i>", ids 0 to kBodyCount - 1, in a world whose
  // pages hold `page_bytes`.
  void make_world(std::size_t page_bytes) {
    tumble::v1::Scene scene;
    for (int i = 0; i < kBodyCount; ++i) {
      auto* body = scene.add_bodies();
      body->set_name("body-" + std::to_string(i));
      body->mutable_shape()->mutable_sphere()->set_radius(0.5);
      body->set_mass(1);
      body->mutable_position()->set_x(3.0 * i);
    }
    SimConfig config;
    config.max_bodies = kBodyCount;
    config.list_page_bytes = page_bytes;
    ASSERT_TRUE(Simulation::create(scene, config, &sim_).ok());
  }

  tumble::v1::BodyList page(std::uint32_t start_id, std::uint32_t max_bodies = 0) {
    ClientMessage message;
    message.set_request_id(7);
    message.mutable_list_bodies()->set_start_id(start_id);
    message.mutable_list_bodies()->set_max_bodies(max_bodies);
    ServerMessage reply;
    sim_->submit(Command{message, [&](ServerMessage m) { reply = std::move(m); }});
    sim_->run_tick();
    EXPECT_TRUE(reply.has_body_list());
    return reply.body_list();
  }

  // Follows the pages from the first; the ids listed, in order.
  std::vector<std::uint32_t> list_all(std::size_t* pages) {
    std::vector<std::uint32_t> ids;
    std::uint32_t start = 0;
    *pages = 0;
    do {
      const tumble::v1::BodyList list = page(start);
      ++*pages;
      for (const auto& body : list.bodies()) ids.push_back(body.id());
      EXPECT_TRUE(list.next_start_id() == 0 || list.next_start_id() > start);
      start = list.next_start_id();
    } while (start != 0 && *pages < 1000);
    return ids;
  }

  std::unique_ptr<Simulation> sim_;
};

TEST_F(ListBodiesTest, AWorldThatFitsInOnePageComesWhole) {
  make_world(std::size_t{1} << 20);
  const tumble::v1::BodyList list = page(0);
  ASSERT_EQ(list.bodies_size(), kBodyCount);
  EXPECT_EQ(list.next_start_id(), 0u);
  EXPECT_EQ(list.total_bodies(), static_cast<std::uint32_t>(kBodyCount));
  EXPECT_EQ(list.request_id(), 7u);
  EXPECT_EQ(list.bodies(123).name(), "body-123");
  EXPECT_EQ(list.bodies(123).position().x(), 369.0);
}

TEST_F(ListBodiesTest, PagesHoldAtMostThePageSizeAndTogetherEveryBodyOnce) {
  constexpr std::size_t kPageBytes = 4096;
  make_world(kPageBytes);
  // An empty request, as a client from before paging sends it: the first page, and word of more.
  const tumble::v1::BodyList first = page(0);
  EXPECT_GT(first.bodies_size(), 1);
  EXPECT_LT(first.bodies_size(), kBodyCount);
  EXPECT_EQ(first.next_start_id(), static_cast<std::uint32_t>(first.bodies_size()));
  EXPECT_EQ(first.total_bodies(), static_cast<std::uint32_t>(kBodyCount));
  tumble::v1::BodyList bodies_only = first;
  bodies_only.clear_request_id();
  bodies_only.clear_tick();
  bodies_only.clear_next_start_id();
  bodies_only.clear_total_bodies();
  EXPECT_LE(bodies_only.ByteSizeLong(), kPageBytes);

  std::size_t pages = 0;
  const std::vector<std::uint32_t> ids = list_all(&pages);
  ASSERT_EQ(ids.size(), static_cast<std::size_t>(kBodyCount));
  for (std::size_t i = 0; i < ids.size(); ++i) EXPECT_EQ(ids[i], i);
  EXPECT_GE(pages, static_cast<std::size_t>(kBodyCount / first.bodies_size()));
}

TEST_F(ListBodiesTest, StartIdAndMaxBodiesChooseThePage) {
  make_world(std::size_t{1} << 20);
  tumble::v1::BodyList list = page(100, 10);
  ASSERT_EQ(list.bodies_size(), 10);
  EXPECT_EQ(list.bodies(0).id(), 100u);
  EXPECT_EQ(list.bodies(9).id(), 109u);
  EXPECT_EQ(list.next_start_id(), 110u);
  list = page(kBodyCount - 3, 3);
  EXPECT_EQ(list.bodies_size(), 3);
  EXPECT_EQ(list.next_start_id(), 0u);  // nothing after it
  list = page(kBodyCount + 5);
  EXPECT_EQ(list.bodies_size(), 0);
  EXPECT_EQ(list.next_start_id(), 0u);
  EXPECT_EQ(list.total_bodies(), static_cast<std::uint32_t>(kBodyCount));
}

TEST_F(ListBodiesTest, APageLargerThanTheBodyItStartsWithStillHoldsIt) {
  make_world(1);  // smaller than any body: one body a page
  const tumble::v1::BodyList list = page(4);
  ASSERT_EQ(list.bodies_size(), 1);
  EXPECT_EQ(list.bodies(0).id(), 4u);
  EXPECT_EQ(list.next_start_id(), 5u);
}

TEST_F(ListBodiesTest, RemovedBodiesAreSkippedAndTheNextStartIdIsAnIdThatExists) {
  make_world(std::size_t{1} << 20);
  for (std::uint32_t id = 10; id < 20; ++id) {
    ClientMessage remove;
    remove.mutable_remove_body()->mutable_body()->set_id(id);
    sim_->submit(Command{remove, nullptr});
  }
  sim_->run_tick();
  tumble::v1::BodyList list = page(5, 5);
  EXPECT_EQ(list.bodies(4).id(), 9u);
  EXPECT_EQ(list.next_start_id(), 20u);
  list = page(12, 1);
  EXPECT_EQ(list.bodies(0).id(), 20u);
  EXPECT_EQ(list.total_bodies(), static_cast<std::uint32_t>(kBodyCount - 10));
}

}  // namespace
}  // namespace tumble::sim
