# TUMBLE_SANITIZE=address,undefined or thread instruments every target.
if(TUMBLE_SANITIZE)
  set(_flags -fsanitize=${TUMBLE_SANITIZE} -fno-omit-frame-pointer -g)
  if(TUMBLE_SANITIZE MATCHES "undefined")
    list(APPEND _flags -fno-sanitize-recover=undefined)
  endif()
  add_compile_options(${_flags})
  add_link_options(-fsanitize=${TUMBLE_SANITIZE})
endif()
