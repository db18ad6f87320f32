// The files the HTTP endpoint serves: the embedded web/dist
// (web/embedded_files.h), each under "/" + its path, and index.html also
// under "/". Each has a Content-Type told by its extension.
//
// Thread: immutable data; any thread.
#pragma once

#include <string_view>

namespace tumble::net {

struct StaticAsset {
  std::string_view path;          // "index.html", "viewer.js"
  std::string_view content_type;  // "text/html; charset=utf-8", ...
  std::string_view bytes;
};

// The asset for an HTTP request target's path ("/", "/viewer.js"; a query
// string is ignored), or nullptr when there is none.
const StaticAsset* find_static_asset(std::string_view target);

// The Content-Type for a file name, by its extension: html, js, mjs, css,
// png, svg, json, wasm, map, ico, txt; application/octet-stream otherwise.
std::string_view content_type_for(std::string_view path);

}  // namespace tumble::net
