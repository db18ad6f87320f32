#include "test_paths.h"

namespace tumble::test {

const char* tumbled_path() { return TUMBLE_TUMBLED_PATH; }
const char* tumble_cli_path() { return TUMBLE_CLI_PATH; }
const char* web_dist_dir() { return TUMBLE_WEB_DIST; }
const char* scenes_dir() { return TUMBLE_SCENES_DIR; }
const char* nats_auth_conf_path() { return TUMBLE_NATS_AUTH_CONF; }

}  // namespace tumble::test
