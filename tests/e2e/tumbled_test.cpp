// tumbled as a user starts it: flags, scene errors, signals.
#include <gtest/gtest.h>

#include <poll.h>
#include <sched.h>
#include <sys/inotify.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include "test_scenes.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

TEST(Tumbled, StopsCleanlyOnSigterm) {
  TumbledProcess server(kFallingCrateScene);
  ASSERT_TRUE(server.started()) << server.log();
  server.process().signal(SIGTERM);
  const auto code = server.process().wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value()) << "tumbled did not stop";
  EXPECT_EQ(*code, 0) << server.log();
  EXPECT_NE(server.log().find("SIGTERM"), std::string::npos) << server.log();
}

TEST(Tumbled, StopsCleanlyOnSigint) {
  TumbledProcess server(kFallingCrateScene);
  ASSERT_TRUE(server.started()) << server.log();
  server.process().signal(SIGINT);
  const auto code = server.process().wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0) << server.log();
}

// A supervisor that signals tumbled the moment --port-file appears (here:
// woken by inotify as the file is renamed into place) finds the handlers
// installed: tumbled stops cleanly, never killed by the signal's default
// action. Ten starts, SIGINT and SIGTERM in turn.
TEST(Tumbled, ASignalAsSoonAsThePortFileAppearsStopsItCleanly) {
  for (int attempt = 0; attempt < 10; ++attempt) {
    const int signal_number = attempt % 2 == 0 ? SIGINT : SIGTERM;
    const std::string dir = make_temp_dir();
    const int watch = inotify_init1(IN_CLOEXEC);
    ASSERT_GE(watch, 0);
    ASSERT_GE(inotify_add_watch(watch, dir.c_str(), IN_MOVED_TO), 0);
    ChildProcess server({tumbled_path(), "--listen", "127.0.0.1:0", "--port-file", dir + "/port"}, dir + "/log");
    ASSERT_TRUE(server.started());
    alignas(inotify_event) char events[4096];
    bool appeared = false;
    while (!appeared) {
      // Bounded: a tumbled that never listens fails the test, not hangs it.
      pollfd ready{watch, POLLIN, 0};
      ASSERT_EQ(poll(&ready, 1, 10000), 1) << "no port file within 10 s\n" << read_file(dir + "/log");
      const ssize_t length = read(watch, events, sizeof events);
      ASSERT_GT(length, 0);
      for (ssize_t at = 0; at < length;) {
        const auto* event = reinterpret_cast<const inotify_event*>(events + at);
        if (event->len > 0 && std::string(event->name) == "port") appeared = true;
        at += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
      }
    }
    server.signal(signal_number);
    close(watch);
    const auto code = server.wait(std::chrono::seconds(20));
    ASSERT_TRUE(code.has_value()) << "tumbled did not stop";
    EXPECT_EQ(*code, 0) << "attempt " << attempt << "\n" << read_file(dir + "/log");
    EXPECT_NE(read_file(dir + "/log").find(signal_number == SIGINT ? "received SIGINT" : "received SIGTERM"),
              std::string::npos)
        << read_file(dir + "/log");
  }
}

TEST(Tumbled, InvalidSceneStopsItWithAMessageNamingTheField) {
  const std::string dir = make_temp_dir();
  const std::string path = dir + "/bad.json";
  std::ofstream(path) << R"({"bodies": [{"name": "a", "shape": {"sphere": {"radius": -2}}, "mass": 1}]})";
  const CommandResult result = run_command({tumbled_path(), "--scene", path, "--listen", "127.0.0.1:0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("bodies[0].shape.sphere.radius"), std::string::npos) << result.err;
}

TEST(Tumbled, UnreadableSceneNamesThePath) {
  const CommandResult result =
      run_command({tumbled_path(), "--scene", "/nonexistent/scene.json", "--listen", "127.0.0.1:0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("/nonexistent/scene.json"), std::string::npos) << result.err;
}

TEST(Tumbled, BadFlagsAreUsageErrors) {
  EXPECT_EQ(run_command({tumbled_path(), "--listen", "no-port"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--tick-rate", "fast"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--log-level", "loud"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--no-such-flag"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--version"}).exit_code, 0);
}

TEST(Tumbled, AddressInUseIsAClearError) {
  TumbledProcess first(kFallingCrateScene);
  ASSERT_TRUE(first.started());
  const CommandResult second = run_command({tumbled_path(), "--listen", first.server()});
  EXPECT_EQ(second.exit_code, 1);
  EXPECT_NE(second.err.find("cannot bind"), std::string::npos) << second.err;
}

// The scheduling policy and priority of each of a process's threads, by
// thread name (/proc/PID/task/*/comm); the main thread, which runs
// tumbled's network (io.run()), as "main". Threads a sanitizer's runtime
// starts carry the process's name, "tumbled".
struct ThreadScheduling {
  int policy = -1;
  int priority = -1;
  std::uint64_t slice_ns = 0;  // a fair-scheduled thread's time slice (sched_getattr), 0 where not reported
  int count = 0;               // threads of that name (the last one's policy is kept)
};

// sched_getattr's result (linux/sched/types.h clashes with glibc's sched.h).
struct SchedAttr {
  std::uint32_t size;
  std::uint32_t sched_policy;
  std::uint64_t sched_flags;
  std::int32_t sched_nice;
  std::uint32_t sched_priority;
  std::uint64_t sched_runtime;
  std::uint64_t sched_deadline;
  std::uint64_t sched_period;
};

std::uint64_t slice_of(pid_t tid) {
  SchedAttr attr{};
  if (syscall(SYS_sched_getattr, tid, &attr, sizeof attr, 0U) != 0) return 0;
  return attr.sched_runtime;
}

// Whether this kernel lets a thread choose its fair time slice (EEVDF,
// Linux 6.12 and later), tried on a thread of its own.
bool kernel_takes_slices() {
  bool taken = false;
  std::thread([&] {
    SchedAttr attr{};
    attr.size = sizeof attr;
    attr.sched_policy = SCHED_OTHER;
    attr.sched_runtime = 200'000;
    taken = syscall(SYS_sched_setattr, 0, &attr, 0U) == 0 && slice_of(static_cast<pid_t>(gettid())) == 200'000;
  }).join();
  return taken;
}
// The threads of pid now: id and name (/proc/<pid>/task/<tid>/comm).
std::vector<std::pair<pid_t, std::string>> threads_of(pid_t pid) {
  std::vector<std::pair<pid_t, std::string>> threads;
  std::error_code error;
  for (const auto& task : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task", error)) {
    std::string name = read_file(task.path().string() + "/comm");
    if (!name.empty() && name.back() == '\n') name.pop_back();
    threads.emplace_back(static_cast<pid_t>(std::stol(task.path().filename().string())), std::move(name));
  }
  return threads;
}

std::map<std::string, ThreadScheduling> thread_scheduling(pid_t pid) {
  std::map<std::string, ThreadScheduling> threads;
  for (const auto& [tid, name] : threads_of(pid)) {
    ThreadScheduling scheduling;
    scheduling.policy = sched_getscheduler(tid);
    sched_param param{};
    if (sched_getparam(tid, &param) == 0) scheduling.priority = param.sched_priority;
    scheduling.slice_ns = slice_of(tid);
    ThreadScheduling& entry = threads[tid == pid ? std::string("main") : name];
    scheduling.count = entry.count + 1;
    entry = scheduling;
  }
  return threads;
}

// The threads of pid once every one of `expected` (thread name -> count)
// has started, or after 10 s, whichever is first. The threads tumbled
// starts name themselves once running, which may be after the port file is
// written: the sim thread, the physics helpers (which the sim thread
// starts) and the checkpoint writer.
std::map<std::string, ThreadScheduling> threads_once_running(pid_t pid, const std::map<std::string, int>& expected) {
  auto ready = [&](const std::map<std::string, ThreadScheduling>& threads) {
    for (const auto& [name, count] : expected) {
      if (!threads.contains(name) || threads.at(name).count != count) return false;
    }
    return true;
  };
  auto threads = thread_scheduling(pid);
  for (int i = 0; i < 200 && !ready(threads); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    threads = thread_scheduling(pid);
  }
  return threads;
}

// Whether this process may put a thread under SCHED_FIFO at `priority`
// (root or CAP_SYS_NICE, or RLIMIT_RTPRIO), tried on a thread of its own.
bool may_use_fifo(int priority) {
  bool allowed = false;
  std::thread([&] {
    sched_param param{};
    param.sched_priority = priority;
    allowed = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
  }).join();
  return allowed;
}

TEST(Tumbled, ThreadsRunUnderOrdinarySchedulingByDefault) {
  TumbledProcess server(kFallingCrateScene, {"--physics-threads", "2"});
  ASSERT_TRUE(server.started()) << server.log();
  const auto threads = threads_once_running(server.process().pid(), {{"tumbled-sim", 1}, {"tumble-physics", 1}});
  ASSERT_TRUE(threads.contains("tumbled-sim")) << server.log();
  ASSERT_TRUE(threads.contains("tumble-physics")) << server.log();
  for (const auto& [name, scheduling] : threads) EXPECT_EQ(scheduling.policy, SCHED_OTHER) << name;
}

TEST(Tumbled, TheSimAndNetworkThreadsAskForAShortSlice) {
  if (!kernel_takes_slices()) GTEST_SKIP() << "this kernel does not let a thread choose its time slice";
  const std::string dir = make_temp_dir();
  TumbledProcess server(kFallingCrateScene,
                        {"--physics-threads", "2", "--state", dir + "/world.state", "--checkpoint-interval", "60"});
  ASSERT_TRUE(server.started()) << server.log();
  const auto threads =
      threads_once_running(server.process().pid(), {{"tumbled-sim", 1}, {"tumble-physics", 1}, {"tumbled-saver", 1}});
  ASSERT_TRUE(threads.contains("main")) << server.log();
  ASSERT_TRUE(threads.contains("tumbled-sim")) << server.log();
  ASSERT_TRUE(threads.contains("tumble-physics")) << server.log();
  ASSERT_TRUE(threads.contains("tumbled-saver")) << server.log();
  // 100 us (server/realtime.h), for the threads whose wake-ups must not
  // wait out another thread's slice, the helpers inheriting the sim's.
  EXPECT_EQ(threads.at("main").slice_ns, 100'000u);
  EXPECT_EQ(threads.at("tumbled-sim").slice_ns, 100'000u);
  EXPECT_EQ(threads.at("tumble-physics").slice_ns, 100'000u);
  EXPECT_NE(threads.at("tumbled-saver").slice_ns, 100'000u) << "the checkpoint writer keeps the default";
  for (const auto& [name, scheduling] : threads) EXPECT_EQ(scheduling.policy, SCHED_OTHER) << name;
}

TEST(Tumbled, RealtimePriorityPutsTheSimAndNetworkThreadsUnderFifo) {
  if (!may_use_fifo(3)) GTEST_SKIP() << "this process may not use SCHED_FIFO (no CAP_SYS_NICE, ulimit -r 0)";
  const std::string dir = make_temp_dir();
  TumbledProcess server(kFallingCrateScene, {"--realtime-priority", "3", "--physics-threads", "3", "--state",
                                             dir + "/world.state", "--checkpoint-interval", "60", "--keep-cpus-awake"});
  ASSERT_TRUE(server.started()) << server.log();
  const auto threads =
      threads_once_running(server.process().pid(), {{"tumbled-sim", 1}, {"tumble-physics", 2}, {"tumbled-saver", 1}});
  ASSERT_TRUE(threads.contains("main")) << server.log();
  ASSERT_TRUE(threads.contains("tumbled-sim")) << server.log();
  ASSERT_TRUE(threads.contains("tumbled-saver")) << server.log();
  // The main thread runs the network (io.run()); the sim thread steps.
  EXPECT_EQ(threads.at("main").policy, SCHED_FIFO);
  EXPECT_EQ(threads.at("main").priority, 3);
  EXPECT_EQ(threads.at("tumbled-sim").policy, SCHED_FIFO);
  EXPECT_EQ(threads.at("tumbled-sim").priority, 3);
  // The physics helpers, started by the sim thread, inherit its scheduling:
  // the step waits for the islands they take.
  ASSERT_TRUE(threads.contains("tumble-physics")) << server.log();
  EXPECT_EQ(threads.at("tumble-physics").count, 2);
  EXPECT_EQ(threads.at("tumble-physics").policy, SCHED_FIFO);
  EXPECT_EQ(threads.at("tumble-physics").priority, 3);
  // The checkpoint writer writes files: it stays ordinary.
  EXPECT_EQ(threads.at("tumbled-saver").policy, SCHED_OTHER);
  // A spinner never spins under the sim's policy: it is started first and
  // lowers itself before it spins.
  ASSERT_TRUE(threads.contains("tumbled-awake")) << server.log();
  EXPECT_EQ(threads.at("tumbled-awake").policy, SCHED_IDLE);
  EXPECT_NE(server.log().find("SCHED_FIFO at priority 3"), std::string::npos) << server.log();

  // And it serves and steps as ever.
  const CommandResult bodies = server.cli({"bodies"});
  EXPECT_EQ(bodies.exit_code, 0) << bodies.err;
  EXPECT_NE(bodies.out.find("crate"), std::string::npos) << bodies.out;
  server.process().signal(SIGTERM);
  const auto code = server.process().wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0) << server.log();
}

// Nanoseconds a thread has spent on a CPU (the first field of
// /proc/<pid>/task/<tid>/schedstat); 0 when unreadable.
std::uint64_t time_on_cpu_ns(pid_t pid, pid_t tid) {
  std::ifstream file("/proc/" + std::to_string(pid) + "/task/" + std::to_string(tid) + "/schedstat");
  std::uint64_t ns = 0;
  file >> ns;
  return ns;
}

TEST(Tumbled, KeepCpusAwakePinsAnIdleSpinnerToEachCpu) {
  TumbledProcess server(kFallingCrateScene, {"--keep-cpus-awake"});
  ASSERT_TRUE(server.started()) << server.log();
  const pid_t pid = server.process().pid();
  cpu_set_t mask;
  ASSERT_EQ(sched_getaffinity(pid, sizeof mask, &mask), 0);
  const int cpus = CPU_COUNT(&mask);
  // The spinners run before tumbled listens: one per CPU of its mask, each
  // pinned to a CPU of its own and under SCHED_IDLE.
  std::vector<pid_t> spinners;
  std::set<int> pinned;
  for (const auto& [tid, name] : threads_of(pid)) {
    if (name != "tumbled-awake") continue;
    spinners.push_back(tid);
    EXPECT_EQ(sched_getscheduler(tid), SCHED_IDLE) << tid;
    cpu_set_t own;
    ASSERT_EQ(sched_getaffinity(tid, sizeof own, &own), 0);
    EXPECT_EQ(CPU_COUNT(&own), 1) << tid;
    for (std::size_t cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
      if (CPU_ISSET(cpu, &own)) {
        EXPECT_TRUE(CPU_ISSET(cpu, &mask)) << cpu;
        pinned.insert(static_cast<int>(cpu));
      }
    }
  }
  EXPECT_EQ(static_cast<int>(spinners.size()), cpus);
  EXPECT_EQ(static_cast<int>(pinned.size()), cpus);
  EXPECT_NE(server.log().find("keeping " + std::to_string(cpus) + " CPUs awake"), std::string::npos) << server.log();
  // They spin: each one's time on its CPU grows (under SCHED_IDLE, only by
  // what the machine's other work leaves; bounded at 20 s).
  for (const pid_t tid : spinners) {
    const std::uint64_t start = time_on_cpu_ns(pid, tid);
    bool grew = false;
    for (int i = 0; i < 200 && !grew; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      grew = time_on_cpu_ns(pid, tid) > start;
    }
    EXPECT_TRUE(grew) << "the spinner " << tid << " never ran";
  }
  // And it serves and steps as ever, and stops cleanly.
  const CommandResult bodies = server.cli({"bodies"});
  EXPECT_EQ(bodies.exit_code, 0) << bodies.err;
  EXPECT_NE(bodies.out.find("crate"), std::string::npos) << bodies.out;
  server.process().signal(SIGTERM);
  const auto code = server.process().wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value()) << "tumbled did not stop";
  EXPECT_EQ(*code, 0) << server.log();
}

TEST(Tumbled, RealtimePriorityRefusedIsAClearErrorBeforeListening) {
  // No RLIMIT_RTPRIO, and (as root) no CAP_SYS_NICE after exec: the kernel
  // refuses SCHED_FIFO. prlimit and setpriv are util-linux's (essential in
  // Debian).
  std::vector<std::string> argv = {"/usr/bin/prlimit", "--rtprio=0"};
  if (geteuid() == 0) argv.insert(argv.end(), {"/usr/bin/setpriv", "--bounding-set", "-sys_nice"});
  const std::string dir = make_temp_dir();
  argv.insert(argv.end(),
              {tumbled_path(), "--listen", "127.0.0.1:0", "--port-file", dir + "/port", "--realtime-priority", "5"});
  const CommandResult result = run_command(argv);
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("--realtime-priority 5: the kernel refused SCHED_FIFO"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find(": it needs CAP_SYS_NICE, or an RLIMIT_RTPRIO of at least 5"), std::string::npos)
      << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/port")) << "it listened before failing";
}

TEST(Tumbled, RealtimePriorityIsGrantedByRlimitRtprioWithoutPrivilege) {
  // As the image's unprivileged user with docker run --ulimit rtprio=5:
  // RLIMIT_RTPRIO 5 and no CAP_SYS_NICE.
  if (geteuid() != 0 || run_command({"/usr/bin/prlimit", "--rtprio=5", "/bin/true"}).exit_code != 0) {
    GTEST_SKIP() << "this process may not raise RLIMIT_RTPRIO (no CAP_SYS_RESOURCE)";
  }
  const std::string dir = make_temp_dir();
  ChildProcess server(
      {"/usr/bin/prlimit", "--rtprio=5", "/usr/bin/setpriv", "--bounding-set", "-sys_nice", tumbled_path(), "--listen",
       "127.0.0.1:0", "--port-file", dir + "/port", "--realtime-priority", "5"},
      dir + "/log");
  for (int i = 0; i < 200 && !std::filesystem::exists(dir + "/port"); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(std::filesystem::exists(dir + "/port")) << read_file(dir + "/log");
  const auto threads = threads_once_running(server.pid(), {{"tumbled-sim", 1}});
  ASSERT_TRUE(threads.contains("tumbled-sim")) << read_file(dir + "/log");
  EXPECT_EQ(threads.at("tumbled-sim").policy, SCHED_FIFO);
  EXPECT_EQ(threads.at("tumbled-sim").priority, 5);
  EXPECT_EQ(threads.at("main").policy, SCHED_FIFO);
}

TEST(Tumbled, RealtimePriorityInAControlGroupWithoutRealTimeTimeNamesTheGroup) {
  // cgroup v1 with real-time group scheduling: a new group has
  // cpu.rt_runtime_us 0, and the kernel refuses SCHED_FIFO in it even to
  // root. (Under cgroup v2 there is no such limit: nothing to test.)
  const std::string cpu = "/sys/fs/cgroup/cpu";
  if (!std::filesystem::exists(cpu + "/cpu.rt_runtime_us") || !may_use_fifo(5)) {
    GTEST_SKIP() << "no cgroup v1 real-time group scheduling here, or no SCHED_FIFO for this process";
  }
  const std::string group = cpu + "/tumble-test-" + std::to_string(getpid());
  std::error_code error;
  if (!std::filesystem::create_directory(group, error))
    GTEST_SKIP() << "cannot create " << group << ": " << error.message();
  ASSERT_EQ(read_file(group + "/cpu.rt_runtime_us"), "0\n");
  const std::string dir = make_temp_dir();
  // The shell moves itself into the group, then becomes tumbled.
  const CommandResult result =
      run_command({"/bin/sh", "-c", "echo $$ > " + group + "/cgroup.procs && exec \"$0\" \"$@\"", tumbled_path(),
                   "--listen", "127.0.0.1:0", "--port-file", dir + "/port", "--realtime-priority", "5"});
  std::filesystem::remove(group, error);  // empty again once tumbled has exited
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("its control group has no real-time time"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("cpu.rt_runtime_us"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/port")) << "it listened before failing";
}

// --physics-threads N: N - 1 helpers beside the sim thread; 1, none.
TEST(Tumbled, PhysicsThreadsStartThatManyHelpers) {
  {
    TumbledProcess server(kFallingCrateScene, {"--physics-threads", "4"});
    ASSERT_TRUE(server.started()) << server.log();
    const auto threads = threads_once_running(server.process().pid(), {{"tumbled-sim", 1}, {"tumble-physics", 3}});
    ASSERT_TRUE(threads.contains("tumble-physics")) << server.log();
    EXPECT_EQ(threads.at("tumble-physics").count, 3);
    // A reset builds a new world; it gets as many helpers, no more.
    const CommandResult reset = server.cli({"reset"});
    ASSERT_EQ(reset.exit_code, 0) << reset.err;
    const auto after = thread_scheduling(server.process().pid());
    ASSERT_TRUE(after.contains("tumble-physics")) << server.log();
    EXPECT_EQ(after.at("tumble-physics").count, 3);
  }
  TumbledProcess server(kFallingCrateScene, {"--physics-threads", "1"});
  ASSERT_TRUE(server.started()) << server.log();
  // A command answered means the sim thread is past starting its helpers.
  ASSERT_EQ(server.cli({"bodies"}).exit_code, 0) << server.log();
  const auto threads = thread_scheduling(server.process().pid());
  ASSERT_TRUE(threads.contains("tumbled-sim")) << server.log();
  EXPECT_FALSE(threads.contains("tumble-physics"));
  EXPECT_EQ(run_command({tumbled_path(), "--physics-threads", "0"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--physics-threads", "65"}).exit_code, 2);
}

TEST(Tumbled, RealtimePriorityOutsideOneTo99IsAUsageError) {
  EXPECT_EQ(run_command({tumbled_path(), "--realtime-priority", "100"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--realtime-priority", "-1"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--realtime-priority", "high"}).exit_code, 2);
}

}  // namespace
}  // namespace tumble::test
