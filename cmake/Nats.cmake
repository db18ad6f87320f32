# nats::nats: the NATS C client (nats.c, Debian's libnats-dev), as an
# imported target of our own. The package's CMake config names a static
# library it does not ship, so the header and the shared library are found
# directly.
find_path(TUMBLE_NATS_INCLUDE_DIR nats/nats.h)
find_library(TUMBLE_NATS_LIBRARY NAMES nats)
if(NOT TUMBLE_NATS_INCLUDE_DIR OR NOT TUMBLE_NATS_LIBRARY)
  message(FATAL_ERROR "nats.c not found (nats/nats.h, libnats): install libnats-dev (scripts/install-deps.sh)")
endif()
add_library(nats::nats SHARED IMPORTED)
set_target_properties(nats::nats PROPERTIES
  IMPORTED_LOCATION "${TUMBLE_NATS_LIBRARY}"
  INTERFACE_INCLUDE_DIRECTORIES "${TUMBLE_NATS_INCLUDE_DIR}")
