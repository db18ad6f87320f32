// A world that survives restarts, against the real tumbled: --state saves
// it on SIGTERM and resumes it exactly; --checkpoint-interval bounds what a
// kill -9 loses; --record and --replay reproduce a run bit for bit; a
// damaged state file falls back to the one it replaced, and a damaged
// journal is refused at the damaged record.
#include <gtest/gtest.h>

#include <signal.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "poll_until.h"
#include "sim/state_file.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using nlohmann::json;

// Contacts, sleep, friction and bounces: what a replay must reproduce.
const char* kPile = R"({"bodies": [
    {"name": "ground", "static": true, "shape": {"plane": {}}},
    {"name": "a", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 1, "position": [0, 0.5, 0]},
    {"name": "b", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 1, "position": [0.2, 1.5, 0]},
    {"name": "c", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 1, "position": [-0.1, 2.5, 0.1]},
    {"name": "ball", "shape": {"sphere": {"radius": 0.3}}, "mass": 1, "restitution": 0.7, "position": [3, 4, 0]},
    {"name": "pill", "shape": {"capsule": {"radius": 0.2, "half_height": 0.4}}, "mass": 1, "position": [-3, 1, 0]}]})";

// Waits until `server` has stepped `ticks` past the tick it is at now.
void wait_for_ticks(const TumbledProcess& server, std::uint64_t ticks) {
  const std::uint64_t target = run_json(server, {"stats"})["tick"].get<std::uint64_t>() + ticks;
  EXPECT_TRUE(poll_until([&] { return run_json(server, {"stats"})["tick"].get<std::uint64_t>() >= target; }))
      << "the server did not reach tick " << target;
}

TEST(Persistence, SigtermSavesTheWorldAndAStartResumesItExactly) {
  const std::string state = make_temp_dir() + "/world.state";
  json before;
  {
    TumbledProcess saving(kFloatingScene, {"--state", state});
    ASSERT_TRUE(saving.started()) << saving.log();
    run_ok(saving, {"impulse", "crate", "--impulse", "2", "0", "0"});
    run_ok(saving, {"force", "ball", "--force", "1", "0", "0", "--persistent"});
    run_ok(saving,
           {"spawn", "extra", "--sphere", "0.2", "--mass", "3", "--at", "0", "10", "0", "--velocity", "0", "1", "0"});
    run_ok(saving, {"remove", "extra"});  // its id must stay unused after the restart
    run_ok(saving, {"pause"});
    before = run_json(saving, {"bodies"});
    EXPECT_EQ(terminate(saving), 0) << saving.log();
    EXPECT_NE(saving.log().find("saved the world at tick " + std::to_string(before["tick"].get<std::uint64_t>())),
              std::string::npos)
        << saving.log();
  }
  TumbledProcess resumed(R"({"bodies": []})", {"--state", state});
  ASSERT_TRUE(resumed.started()) << resumed.log();
  const json after = run_json(resumed, {"bodies"});
  // The same tick and every number the same to the last bit (the CLI prints
  // doubles with all 17 digits).
  EXPECT_EQ(after["tick"], before["tick"]);
  EXPECT_EQ(after["bodies"], before["bodies"]);
  EXPECT_TRUE(run_json(resumed, {"stats"})["paused"].get<bool>());

  // The persistent force came back too: 240 ticks of 1 N on 1 kg add 1 m/s.
  run_ok(resumed, {"step", "240"});
  const json later = run_json(resumed, {"bodies"});
  EXPECT_NEAR(body(later, "ball")["linear_velocity"][0].get<double>() -
                  body(before, "ball")["linear_velocity"][0].get<double>(),
              1.0, 1e-9);
  EXPECT_NEAR(body(later, "crate")["position"][0].get<double>() - body(before, "crate")["position"][0].get<double>(),
              1.0, 1e-9);
  // A new body gets a fresh id, not the removed one's.
  const json spawned = run_json(resumed, {"spawn", "next", "--sphere", "0.2", "--mass", "1", "--at", "5", "5", "5"});
  EXPECT_EQ(spawned["body_id"].get<std::uint32_t>(), 3u);
}

TEST(Persistence, CheckpointsBoundWhatAKillLoses) {
  const std::string state = make_temp_dir() + "/world.state";
  TumbledProcess server(kFloatingScene, {"--state", state, "--checkpoint-interval", "0.25"});
  ASSERT_TRUE(server.started()) << server.log();
  const std::uint64_t pushed = run_json(server, {"impulse", "crate", "--impulse", "2", "0", "0"})["applied_tick"];
  // A checkpoint written 0.75 s (180 ticks) after the impulse or later, then the kill.
  ASSERT_TRUE(poll_until([&] { return checkpoint_tick(state) >= pushed + 180; }))
      << "no checkpoint 180 ticks after the impulse\n"
      << server.log();
  // Stats say so too, once the saver has counted it.
  json saved;
  ASSERT_TRUE(poll_until([&] {
    saved = run_json(server, {"stats"})["checkpoints"];
    return saved["last_tick"].get<std::uint64_t>() >= pushed + 180;
  })) << saved.dump();
  EXPECT_EQ(saved["destination"], state);
  EXPECT_EQ(saved["interval_s"], 0.25);
  EXPECT_GE(saved["written"].get<std::uint64_t>(), 1u);
  EXPECT_EQ(saved["failed"], 0);
  EXPECT_GT(saved["last_bytes"].get<std::uint64_t>(), 0u);
  const std::uint64_t seen = run_json(server, {"stats"})["tick"].get<std::uint64_t>();
  server.process().signal(SIGKILL);
  ASSERT_EQ(server.process().wait(std::chrono::seconds(10)), 128 + SIGKILL);

  TumbledProcess resumed(R"({"bodies": []})", {"--state", state});
  ASSERT_TRUE(resumed.started()) << resumed.log();
  const json list = run_json(resumed, {"bodies"});
  const std::uint64_t tick = list["tick"].get<std::uint64_t>();
  // At most one interval (60 ticks) older than what was seen before the kill,
  // plus a generous allowance for a loaded machine; never nothing.
  EXPECT_GT(tick + 240, seen) << "resumed at tick " << tick << ", saw tick " << seen << " before the kill";
  EXPECT_GT(tick, 0u);
  // The crate is on its track: x = 1 m/s * (time since the impulse).
  const json& crate = body(list, "crate");
  EXPECT_DOUBLE_EQ(crate["linear_velocity"][0].get<double>(), 1.0);
  EXPECT_GT(crate["position"][0].get<double>(), 0.5);
  // The checkpoint kept the scene too: Reset goes back to it.
  run_ok(resumed, {"reset"});
  const json reset_list = run_json(resumed, {"bodies"});
  const json& reset_crate = body(reset_list, "crate");
  EXPECT_EQ(reset_crate["position"][0].get<double>(), 0.0);
  EXPECT_EQ(reset_crate["linear_velocity"][0].get<double>(), 0.0);
}

TEST(Persistence, AReplayOfARecordedRunEndsInTheSameWorldBitForBit) {
  const std::string dir = make_temp_dir();
  const std::string recorded_state = dir + "/recorded.state";
  const std::string journal = dir + "/run.journal";
  {
    TumbledProcess server(kPile, {"--record", journal, "--state", recorded_state});
    ASSERT_TRUE(server.started()) << server.log();
    // Commands of every kind, at whatever ticks the machine's timing gives.
    run_ok(server, {"force", "c", "--force", "0", "0", "40", "--duration", "0.3"});
    run_ok(server, {"impulse", "ball", "--impulse", "-3", "0", "0"});
    run_ok(server, {"spawn", "late", "--box", "0.3", "0.3", "0.3", "--mass", "2", "--at", "0", "6", "0"});
    wait_for_ticks(server, 48);
    run_ok(server, {"pause"});
    run_ok(server, {"step", "7"});
    run_ok(server, {"torque", "pill", "--torque", "0", "2", "0", "--persistent"});
    run_ok(server, {"set", "a", "--velocity", "0", "0", "1"});
    run_ok(server, {"resume"});
    wait_for_ticks(server, 72);
    run_ok(server, {"remove", "b"});
    run_ok(server, {"clear", "pill"});
    run_ok(server, {"tick-rate", "120"});
    run_ok(server, {"impulse", "a", "--impulse", "1", "0", "0", "--at", "0", "1", "0"});
    wait_for_ticks(server, 36);
    ASSERT_EQ(terminate(server), 0) << server.log();
  }
  const std::string replayed_state = dir + "/replayed.state";
  TumbledProcess replay(kPile, {"--replay", journal, "--state", replayed_state});
  ASSERT_TRUE(replay.started()) << replay.log();
  EXPECT_NE(replay.log().find("replayed 12 commands"), std::string::npos) << replay.log();
  ASSERT_EQ(terminate(replay), 0) << replay.log();

  tumble::v1::WorldState recorded;
  tumble::v1::WorldState replayed;
  bool exists = false;
  ASSERT_TRUE(sim::read_state_file(recorded_state, &recorded, &exists).ok());
  ASSERT_TRUE(sim::read_state_file(replayed_state, &replayed, &exists).ok());
  // The replay stops paused where the run stopped; all else must be equal.
  EXPECT_TRUE(replayed.paused());
  replayed.set_paused(recorded.paused());
  EXPECT_EQ(replayed.tick(), recorded.tick());
  ASSERT_EQ(replayed.bodies_size(), recorded.bodies_size());
  EXPECT_EQ(replayed.SerializeAsString(), recorded.SerializeAsString()) << "recorded:\n"
                                                                        << recorded.DebugString() << "\nreplayed:\n"
                                                                        << replayed.DebugString();
}

TEST(Persistence, BadFilesAndFlagsAreClearErrors) {
  const std::string garbage = make_temp_dir() + "/garbage.state";
  std::ofstream(garbage) << "{\"not\": \"a state\"}";

  CommandResult result = run_command({tumbled_path(), "--listen", "127.0.0.1:0", "--state", garbage});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("not a tumble state file"), std::string::npos) << result.err;

  result = run_command({tumbled_path(), "--listen", "127.0.0.1:0", "--checkpoint-interval", "1"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--state"), std::string::npos) << result.err;

  result = run_command({tumbled_path(), "--listen", "127.0.0.1:0", "--replay", garbage});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("not a tumble journal"), std::string::npos) << result.err;
}

TEST(Persistence, AReplayRefusesAnotherScene) {
  const std::string dir = make_temp_dir();
  const std::string journal = dir + "/run.journal";
  {
    TumbledProcess server(kFloatingScene, {"--record", journal});
    ASSERT_TRUE(server.started()) << server.log();
    ASSERT_EQ(terminate(server), 0);
  }
  const std::string other = dir + "/other.json";
  std::ofstream(other) << kPile;
  const CommandResult result =
      run_command({tumbled_path(), "--listen", "127.0.0.1:0", "--replay", journal, "--scene", other});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("recorded with another scene"), std::string::npos) << result.err;
}

// Sets byte `at` of the file at `path` to its complement.
void flip_byte(const std::string& path, std::size_t at) {
  std::string bytes = read_file(path);
  ASSERT_LT(at, bytes.size());
  bytes[at] = static_cast<char>(~bytes[at]);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

TEST(Persistence, ADamagedStateFileFallsBackToTheOneItReplaced) {
  const std::string state = make_temp_dir() + "/world.state";
  json first;
  {
    TumbledProcess server(kFloatingScene, {"--state", state});
    ASSERT_TRUE(server.started()) << server.log();
    run_ok(server, {"impulse", "crate", "--impulse", "2", "0", "0"});
    run_ok(server, {"pause"});
    first = run_json(server, {"bodies"});
    ASSERT_EQ(terminate(server), 0) << server.log();
  }
  {
    TumbledProcess server(R"({"bodies": []})", {"--state", state});
    ASSERT_TRUE(server.started()) << server.log();
    run_ok(server, {"step", "24"});
    ASSERT_EQ(terminate(server), 0) << server.log();
  }
  ASSERT_TRUE(std::filesystem::exists(state + ".prev"));
  const std::string good_prev = read_file(state + ".prev");
  flip_byte(state, read_file(state).size() / 2);
  const std::string damaged = read_file(state);

  TumbledProcess resumed(R"({"bodies": []})", {"--state", state});
  ASSERT_TRUE(resumed.started()) << resumed.log();
  EXPECT_NE(resumed.log().find("THE STATE FILE IS DAMAGED: " + state + ": bad checksum"), std::string::npos)
      << resumed.log();
  EXPECT_NE(resumed.log().find("resuming from " + state + ".prev"), std::string::npos) << resumed.log();
  // The world of the first run, every number to the last bit.
  const json after = run_json(resumed, {"bodies"});
  EXPECT_EQ(after["tick"], first["tick"]);
  EXPECT_EQ(after["bodies"], first["bodies"]);
  // The damaged file is kept as it was; the good one is left in place.
  EXPECT_EQ(read_file(state + ".damaged"), damaged);
  EXPECT_EQ(read_file(state + ".prev"), good_prev);
  EXPECT_FALSE(std::filesystem::exists(state));
}

TEST(Persistence, BothStateFilesDamagedExitsWithBothReasons) {
  const std::string state = make_temp_dir() + "/world.state";
  {
    TumbledProcess server(kFloatingScene, {"--state", state});
    ASSERT_TRUE(server.started()) << server.log();
    ASSERT_EQ(terminate(server), 0) << server.log();
  }
  std::filesystem::rename(state, state + ".prev");
  flip_byte(state + ".prev", 30);
  std::ofstream(state, std::ios::binary) << "tumble-state-v2\n";  // only its magic number

  const CommandResult result = run_command({tumbled_path(), "--listen", "127.0.0.1:0", "--state", state});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("cannot resume: " + state +
                            ": cut short: 16 bytes end before its 8-byte payload length; and the previous state "
                            "file is unusable too: " +
                            state + ".prev: bad checksum"),
            std::string::npos)
      << result.err;
  EXPECT_EQ(result.err.find("tick_rate_hz"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(state + ".damaged"));
}

// The byte offset of each record of the journal at `path` (the header's first).
std::vector<std::size_t> journal_records(const std::string& path) {
  const std::string bytes = read_file(path);
  std::vector<std::size_t> starts;
  for (std::size_t at = 18; at + 12 <= bytes.size();) {
    starts.push_back(at);
    std::uint32_t length = 0;
    for (std::size_t i = 4; i-- > 0;) length = (length << 8) | static_cast<unsigned char>(bytes[at + i]);
    at += 12 + length;
  }
  return starts;
}

TEST(Persistence, ADamagedJournalIsRefusedAtTheRecordAndATornOneReplaysUpToIt) {
  const std::string dir = make_temp_dir();
  const std::string journal = dir + "/run.journal";
  {
    TumbledProcess server(kFloatingScene, {"--record", journal});
    ASSERT_TRUE(server.started()) << server.log();
    run_ok(server, {"impulse", "crate", "--impulse", "1", "0", "0"});
    run_ok(server, {"impulse", "crate", "--impulse", "0", "1", "0"});
    run_ok(server, {"impulse", "crate", "--impulse", "0", "0", "1"});
    ASSERT_EQ(terminate(server), 0) << server.log();
  }
  const std::vector<std::size_t> records = journal_records(journal);
  ASSERT_EQ(records.size(), 5u);  // the header, three impulses, the end
  const std::string whole = read_file(journal);

  const std::string damaged = dir + "/damaged.journal";
  std::ofstream(damaged, std::ios::binary) << whole;
  flip_byte(damaged, records[2] + 12 + 4);
  CommandResult result = run_command({tumbled_path(), "--listen", "127.0.0.1:0", "--replay", damaged});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("replay of " + damaged + " failed after 1 commands: record 2 at byte " +
                            std::to_string(records[2]) + ": its payload is damaged"),
            std::string::npos)
      << result.err;

  // Killed while writing its end record: the three impulses replay.
  const std::string torn = dir + "/torn.journal";
  std::ofstream(torn, std::ios::binary) << whole.substr(0, whole.size() - 3);
  TumbledProcess replay(kFloatingScene, {"--replay", torn});
  ASSERT_TRUE(replay.started()) << replay.log();
  EXPECT_NE(replay.log().find(torn + ": record 4 at byte " + std::to_string(records[4]) + " is cut short"),
            std::string::npos)
      << replay.log();
  EXPECT_NE(replay.log().find("replayed 3 commands"), std::string::npos) << replay.log();
  // Each impulse of 1 N s gave the 2 kg crate 0.5 m/s.
  const json crate = body(run_json(replay, {"bodies"}), "crate");
  EXPECT_DOUBLE_EQ(crate["linear_velocity"][0].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(crate["linear_velocity"][2].get<double>(), 0.5);
}

}  // namespace
}  // namespace tumble::test
