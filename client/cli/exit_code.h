// The exit statuses of `tumble`.
#pragma once

namespace tumble::cli {

inline constexpr int kExitSuccess = 0;  // the command did what was asked
inline constexpr int kExitFailure = 1;  // the server refused, could not be reached, timed out or closed
inline constexpr int kExitUsage = 2;    // the command line is wrong; nothing was sent

}  // namespace tumble::cli
