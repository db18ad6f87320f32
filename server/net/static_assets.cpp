#include "net/static_assets.h"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "web/embedded_files.h"

namespace tumble::net {

namespace {

// The page served for "/".
constexpr std::string_view kIndex = "index.html";

struct ContentType {
  std::string_view extension;
  std::string_view type;
};

constexpr std::array<ContentType, 11> kContentTypes{{
    {".html", "text/html; charset=utf-8"},
    {".js", "text/javascript; charset=utf-8"},
    {".mjs", "text/javascript; charset=utf-8"},
    {".css", "text/css; charset=utf-8"},
    {".png", "image/png"},
    {".svg", "image/svg+xml"},
    {".json", "application/json"},
    {".wasm", "application/wasm"},
    {".map", "application/json"},
    {".ico", "image/x-icon"},
    {".txt", "text/plain; charset=utf-8"},
}};

char lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

bool ends_with_ignoring_case(std::string_view text, std::string_view suffix) {
  if (text.size() < suffix.size()) return false;
  const std::string_view end = text.substr(text.size() - suffix.size());
  return std::equal(end.begin(), end.end(), suffix.begin(), [](char a, char b) { return lower(a) == lower(b); });
}

// Every embedded file with its type, sorted by path; made once.
const std::vector<StaticAsset>& assets() {
  static const std::vector<StaticAsset> all = [] {
    std::vector<StaticAsset> list;
    for (const web::EmbeddedFile& file : web::embedded_files()) {
      list.push_back({file.path, content_type_for(file.path), file.bytes});
    }
    std::sort(list.begin(), list.end(), [](const StaticAsset& a, const StaticAsset& b) { return a.path < b.path; });
    return list;
  }();
  return all;
}

}  // namespace

std::string_view content_type_for(std::string_view path) {
  for (const ContentType& entry : kContentTypes) {
    if (ends_with_ignoring_case(path, entry.extension)) return entry.type;
  }
  return "application/octet-stream";
}

const StaticAsset* find_static_asset(std::string_view target) {
  std::string_view path = target.substr(0, target.find('?'));
  if (path.empty() || path.front() != '/') return nullptr;
  path.remove_prefix(1);
  if (path.empty()) path = kIndex;
  const auto& all = assets();
  const auto it = std::lower_bound(all.begin(), all.end(), path,
                                   [](const StaticAsset& asset, std::string_view key) { return asset.path < key; });
  return it != all.end() && it->path == path ? &*it : nullptr;
}

}  // namespace tumble::net
