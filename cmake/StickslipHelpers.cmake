# stickslip_add_module(NAME SOURCES a.cpp b.cpp DEPS other_targets)
#   One static library per module: target stickslip_<NAME>, includes rooted at src/
#   (#include "fe/assembly.h").
function(stickslip_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  if(ARG_SOURCES)
    add_library(stickslip_${name} STATIC ${ARG_SOURCES})
    target_include_directories(stickslip_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(stickslip_${name} PUBLIC ${ARG_DEPS})
  else()
    add_library(stickslip_${name} INTERFACE)
    target_include_directories(stickslip_${name} INTERFACE ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(stickslip_${name} INTERFACE ${ARG_DEPS})
  endif()
endfunction()

# stickslip_add_tests(NAME SOURCES a_test.cpp ... DEPS stickslip_fe ...)
#   One GoogleTest executable per module (<NAME>_tests), discovered by CTest at test time.
#   Tests find their data through the STICKSLIP_TEST_DATA_DIR macro (tests/data).
function(stickslip_add_tests name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name}_tests ${ARG_SOURCES})
  target_link_libraries(${name}_tests PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name}_tests PRIVATE
    STICKSLIP_TEST_DATA_DIR="${PROJECT_SOURCE_DIR}/tests/data"
    STICKSLIP_BINARY_DIR="${PROJECT_BINARY_DIR}")
  gtest_discover_tests(${name}_tests DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 60
                       PROPERTIES TIMEOUT 600)
endfunction()
