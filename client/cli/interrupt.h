// Ctrl-C as a request to stop rather than an abrupt end.
#pragma once

#include <chrono>

namespace tumble::cli {

// From now on SIGINT and SIGTERM set a flag instead of ending the process.
// Call from the main thread.
void catch_interrupts();

// Whether SIGINT or SIGTERM arrived since catch_interrupts().
bool interrupted();

// Sleeps for `duration`, looking for an interrupt every 100 ms at most.
// Returns false, early, when one arrived.
bool sleep_unless_interrupted(std::chrono::milliseconds duration);

}  // namespace tumble::cli
