# tumble_warnings(target): the physics project's warning set (one list of
# flags for the whole tree), fatal with TUMBLE_WERROR.
include(${CMAKE_CURRENT_LIST_DIR}/../physics/cmake/TumbleWarnings.cmake)
