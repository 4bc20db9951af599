# Helpers that keep every module's CMakeLists.txt short.
#
# asynevo_module(NAME name SOURCES ... DEPS ...)
#   Builds library asynevo_<name> (static, or INTERFACE when there are no sources) with the public
#   include directory, the project's warning flags and the given dependencies (PUBLIC).
function(asynevo_module)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS" ${ARGN})
  set(target asynevo_${ARG_NAME})
  if(ARG_SOURCES)
    add_library(${target} STATIC ${ARG_SOURCES})
    target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR}/include)
    target_link_libraries(${target} PUBLIC ${ARG_DEPS} PRIVATE asynevo_flags)
    if(ASYNEVO_PYTHON)  # linked into the shared Python module (python/CMakeLists.txt)
      set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    endif()
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${PROJECT_SOURCE_DIR}/include)
    target_link_libraries(${target} INTERFACE ${ARG_DEPS})
  endif()
  add_library(asynevo::${ARG_NAME} ALIAS ${target})
endfunction()

# asynevo_test(NAME name SOURCES ... DEPS ...)
#   One GoogleTest executable per module; tests are discovered so ctest lists each case.
#   Tests run with the repository root as working directory so they can find tests/data.
function(asynevo_test)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS" ${ARGN})
  set(target test_${ARG_NAME})
  add_executable(${target} ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main asynevo_flags)
  target_compile_definitions(${target} PRIVATE ASYNEVO_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                                               ASYNEVO_BINARY_DIR="${PROJECT_BINARY_DIR}")
  gtest_discover_tests(${target} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} DISCOVERY_TIMEOUT 60)
endfunction()

# asynevo_bench(NAME name SOURCES ... DEPS ...): a Google Benchmark executable bench_<name>.
function(asynevo_bench)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS" ${ARGN})
  add_executable(bench_${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(bench_${ARG_NAME} PRIVATE ${ARG_DEPS} benchmark::benchmark asynevo_flags)
  target_compile_definitions(bench_${ARG_NAME} PRIVATE ASYNEVO_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endfunction()
