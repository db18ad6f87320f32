# TUMBLE_LLD (default ON): link with LLVM's lld when the compiler can. The
# executables of the sanitizer builds are large, lld links them much faster
# than GNU ld (docs/development.md "Builds"), and linking is most of what a
# build does once ccache has the objects.
include(CheckLinkerFlag)
option(TUMBLE_LLD "Link with lld when it is installed" ON)
if(TUMBLE_LLD)
  check_linker_flag(CXX -fuse-ld=lld TUMBLE_HAVE_LLD)
  if(TUMBLE_HAVE_LLD)
    add_link_options(-fuse-ld=lld)
  endif()
endif()
