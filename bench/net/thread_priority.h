// The priority of a load generator's client threads: they stand for clients
// on other machines, so on the server's machine they should take only the
// CPU the server leaves.
#pragma once

namespace tumble::bench {

// Gives the calling thread the nice value `nice` (Linux: nice is per
// thread), and with `idle` the SCHED_IDLE policy, under which it runs only
// on a core nothing else wants. Threads it creates afterwards inherit both.
// Best effort: a failure is printed on stderr, prefixed with `program`.
void set_thread_priority(int nice, bool idle, const char* program);

}  // namespace tumble::bench
