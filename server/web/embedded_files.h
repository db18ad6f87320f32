// Files compiled into tumbled: every file of web/dist (the viewer's page and
// its script bundle), embedded at build time by embed_files so that the
// server needs no files beside itself and the build needs no Node.js.
//
// Thread: immutable data; any thread.
#pragma once

#include <span>
#include <string_view>

namespace tumble::web {

struct EmbeddedFile {
  std::string_view path;   // relative to web/dist, '/'-separated: "index.html", "viewer.js"
  std::string_view bytes;  // the file's contents, exactly
};

// Every embedded file, sorted by path. The data lives as long as the program.
std::span<const EmbeddedFile> embedded_files();

}  // namespace tumble::web
