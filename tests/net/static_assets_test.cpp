// The embedded files' lookup and types, and close reasons cut to a
// WebSocket close frame's size.
#include <gtest/gtest.h>

#include "net/static_assets.h"
#include "net/websocket_transport.h"
#include "web/embedded_files.h"

namespace tumble::net {
namespace {

TEST(StaticAssets, ContentTypesByExtension) {
  EXPECT_EQ(content_type_for("index.html"), "text/html; charset=utf-8");
  EXPECT_EQ(content_type_for("viewer.js"), "text/javascript; charset=utf-8");
  EXPECT_EQ(content_type_for("viewer.js.map"), "application/json");
  EXPECT_EQ(content_type_for("style.CSS"), "text/css; charset=utf-8");
  EXPECT_EQ(content_type_for("img/logo.png"), "image/png");
  EXPECT_EQ(content_type_for("icon.svg"), "image/svg+xml");
  EXPECT_EQ(content_type_for("scene.json"), "application/json");
  EXPECT_EQ(content_type_for("physics.wasm"), "application/wasm");
  EXPECT_EQ(content_type_for("README"), "application/octet-stream");
  EXPECT_EQ(content_type_for("html"), "application/octet-stream");
}

TEST(StaticAssets, RootIsTheIndexAndEveryFileIsFoundByItsPath) {
  const StaticAsset* root = find_static_asset("/");
  ASSERT_NE(root, nullptr);
  EXPECT_EQ(root->path, "index.html");
  EXPECT_EQ(root, find_static_asset("/index.html"));
  EXPECT_EQ(root, find_static_asset("/?token=x"));
  for (const web::EmbeddedFile& file : web::embedded_files()) {
    const StaticAsset* asset = find_static_asset("/" + std::string(file.path));
    ASSERT_NE(asset, nullptr) << file.path;
    EXPECT_EQ(asset->bytes, file.bytes);
    EXPECT_EQ(asset->content_type, content_type_for(file.path));
  }
  EXPECT_EQ(find_static_asset(""), nullptr);
  EXPECT_EQ(find_static_asset("index.html"), nullptr);
  EXPECT_EQ(find_static_asset("/index.htm"), nullptr);
  EXPECT_EQ(find_static_asset("/ws"), nullptr);
}

TEST(WebSocketCloseReason, IsCutWithoutSplittingACharacter) {
  EXPECT_EQ(truncate_utf8("short", 123), "short");
  EXPECT_EQ(truncate_utf8(std::string(200, 'a'), 123), std::string(123, 'a'));
  // "é" is two bytes: cutting at 123 would leave half of the one at 122-123.
  const std::string accented = std::string(122, 'a') + "\xc3\xa9" + "tail";
  EXPECT_EQ(truncate_utf8(accented, 123), std::string(122, 'a'));
  EXPECT_EQ(truncate_utf8(accented, 124), std::string(122, 'a') + "\xc3\xa9");
}

}  // namespace
}  // namespace tumble::net
