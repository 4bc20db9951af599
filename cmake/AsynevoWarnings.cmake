# Warning and sanitizer flags applied to every AsynEVO target through asynevo_set_flags().
add_library(asynevo_flags INTERFACE)
target_compile_options(asynevo_flags INTERFACE -Wall -Wextra -Wpedantic -Wshadow=local
                                               -Wnon-virtual-dtor -Wno-unused-parameter)
if(ASYNEVO_WERROR)
  target_compile_options(asynevo_flags INTERFACE -Werror)
endif()
if(ASYNEVO_SANITIZE)
  target_compile_options(asynevo_flags INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer
                                                 -fno-sanitize-recover=undefined)
  target_link_options(asynevo_flags INTERFACE -fsanitize=address,undefined)
endif()
if(ASYNEVO_FUZZ)
  # Coverage instrumentation of all project code, so libFuzzer sees inside the readers.
  target_compile_options(asynevo_flags INTERFACE -fsanitize=fuzzer-no-link)
endif()
if(ASYNEVO_TSAN)
  target_compile_options(asynevo_flags INTERFACE -fsanitize=thread -fno-omit-frame-pointer)
  target_link_options(asynevo_flags INTERFACE -fsanitize=thread)
endif()
