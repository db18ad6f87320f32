// Ctrl-C as a request to stop rather than an abrupt end.
#pragma once

namespace tumble::cli {

// From now on SIGINT and SIGTERM set a flag instead of ending the process.
// Call from the main thread.
void catch_interrupts();

// Whether SIGINT or SIGTERM arrived since catch_interrupts().
bool interrupted();

}  // namespace tumble::cli
