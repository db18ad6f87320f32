// Where the tests find the programs they start and the files of the source
// tree they read: absolute paths of this build, as CMake configured them.
// They live in test_paths.cpp alone, compiled by itself, so that every other
// test file compiles to the same bytes in any clone of the repository and a
// compiler cache finds it (docs/development.md "Builds").
#pragma once

namespace tumble::test {

const char* tumbled_path();         // this build's tumbled
const char* tumble_cli_path();      // this build's tumble CLI
const char* web_dist_dir();         // web/dist: the files tumbled embeds and serves
const char* scenes_dir();           // scenes/: the scene files the repository ships
const char* nats_auth_conf_path();  // docker/nats/auth.conf: the NATS users the image ships

}  // namespace tumble::test
