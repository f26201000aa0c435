# rgbdi_add_module(NAME DEPS <targets...>)
# Builds the static library rgbdi_<NAME> from every .cpp under src/<NAME>/ (headers live in
# include/rgbdi/<NAME>/). One library per pipeline stage keeps link dependencies explicit and lets a
# test link only the stages it exercises.
function(rgbdi_add_module NAME)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB_RECURSE _srcs CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/src/${NAME}/*.cpp")
  file(GLOB_RECURSE _hdrs CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/include/rgbdi/${NAME}/*.h")
  if(NOT _srcs)
    # A stage with no sources yet is simply absent (nothing links against it).
    return()
  endif()
  set(RGBDI_MODULES ${RGBDI_MODULES} ${NAME} CACHE INTERNAL "")
  add_library(rgbdi_${NAME} STATIC ${_srcs} ${_hdrs})
  add_library(rgbdi::${NAME} ALIAS rgbdi_${NAME})
  target_include_directories(rgbdi_${NAME} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_compile_options(rgbdi_${NAME} PRIVATE ${RGBDI_WARNINGS})
  set(_deps)
  foreach(d ${ARG_DEPS})
    # Skip dependencies on stages that do not exist (yet).
    if(d MATCHES "^rgbdi::" AND NOT TARGET ${d})
      continue()
    endif()
    list(APPEND _deps ${d})
  endforeach()
  target_link_libraries(rgbdi_${NAME} PUBLIC ${_deps})
  set_target_properties(rgbdi_${NAME} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()

# rgbdi_add_app(NAME SOURCES <files...> DEPS <targets...>)
function(rgbdi_add_app NAME)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${NAME} ${ARG_SOURCES})
  target_compile_options(${NAME} PRIVATE ${RGBDI_WARNINGS})
  target_link_libraries(${NAME} PRIVATE ${ARG_DEPS})
  set(RGBDI_APPS ${RGBDI_APPS} ${NAME} CACHE INTERNAL "")
endfunction()

# rgbdi_add_test(NAME [SERIAL] SOURCES <files> DEPS <targets...>): one gtest executable, discovered
# by ctest. SERIAL: its tests never run beside another test (ctest -j), for tests that need the
# machine's CPU, e.g. live runs that must keep up with real time.
#
# The tests' properties are set by a ctest include file that runs after the one of the discovered
# tests (which defines the list NAME_TESTS), not through gtest_discover_tests(PROPERTIES): that
# flattens list values into the property pairs, so ENVIRONMENT "A=..;B=.." would lose B. The
# file also records the tests in rgbdi_discovered_tests / rgbdi_serial_tests for the COST file
# (rgbdi_add_test_costs).
function(rgbdi_add_test NAME)
  cmake_parse_arguments(ARG "SERIAL" "" "DEPS;SOURCES" ${ARGN})
  add_executable(${NAME} ${ARG_SOURCES})
  target_compile_options(${NAME} PRIVATE ${RGBDI_WARNINGS})
  target_link_libraries(${NAME} PRIVATE ${ARG_DEPS} rgbdi_testing GTest::gtest GTest::gtest_main)
  gtest_discover_tests(${NAME} DISCOVERY_TIMEOUT 60)
  set(_env "RGBDI_SHARED_DATA=${RGBDI_SHARED_DATA_DIR}" "RGBDI_BIN_DIR=${CMAKE_BINARY_DIR}/bin")
  set(_text "if(${NAME}_TESTS)\n")
  string(APPEND _text
    "  set_tests_properties(\${${NAME}_TESTS} PROPERTIES ENVIRONMENT [==[${_env}]==])\n"
    "  list(APPEND rgbdi_discovered_tests \${${NAME}_TESTS})\n")
  if(ARG_SERIAL)
    string(APPEND _text
      "  set_tests_properties(\${${NAME}_TESTS} PROPERTIES RUN_SERIAL TRUE)\n"
      "  list(APPEND rgbdi_serial_tests \${${NAME}_TESTS})\n")
  endif()
  string(APPEND _text "endif()\n")
  set(_props_file "${CMAKE_CURRENT_BINARY_DIR}/${NAME}_properties.cmake")
  file(WRITE "${_props_file}" "${_text}")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${_props_file}")
endfunction()

# rgbdi_add_test_costs(FILE): ctest COST of the discovered tests from FILE (lines "<seconds>
# <test name>", '#' comments; scripts/test-costs.sh writes it from a run's measured times).
# ctest -j starts the costliest tests first, so the suite does not end with one long test
# running alone. A clean CI tree has no timing data of its own, and where ctest has some (a
# developer's build tree) a test's COST property takes precedence over it. RUN_SERIAL tests get a cost above every other: ctest starts a serial test
# only on an idle machine, so they run first instead of waiting for the parallel tests to drain.
# Call it after every rgbdi_add_test of the directory (its include file runs after theirs).
function(rgbdi_add_test_costs FILE)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${FILE}")
  file(STRINGS "${FILE}" _lines REGEX "^[0-9]")
  set(_pairs)
  set(_max 0)
  foreach(_line IN LISTS _lines)
    if(NOT _line MATCHES "^([0-9]+)[ \t]+(.+)$")
      message(FATAL_ERROR "${FILE}: '${_line}' is not '<seconds> <test name>'")
    endif()
    string(APPEND _pairs "  [==[${CMAKE_MATCH_2}]==] ${CMAKE_MATCH_1}\n")
    if(CMAKE_MATCH_1 GREATER _max)
      set(_max ${CMAKE_MATCH_1})
    endif()
  endforeach()
  math(EXPR _serial_base "${_max} + 1")
  set(_costs_file "${CMAKE_CURRENT_BINARY_DIR}/rgbdi_test_costs.cmake")
  # list(FIND), not if(IN_LIST): ctest reads the file without a policy version.
  file(WRITE "${_costs_file}" "# Generated from ${FILE} by rgbdi_add_test_costs.
set(_rgbdi_costs
${_pairs})
set(_rgbdi_costed_names)
set(_rgbdi_costed_values)
while(_rgbdi_costs)
  list(POP_FRONT _rgbdi_costs _name _cost)
  list(FIND rgbdi_discovered_tests \"\${_name}\" _index)
  if(_index GREATER -1)
    set_tests_properties(\"\${_name}\" PROPERTIES COST \${_cost})
    list(APPEND _rgbdi_costed_names \"\${_name}\")
    list(APPEND _rgbdi_costed_values \${_cost})
  endif()
endwhile()
foreach(_name IN LISTS rgbdi_serial_tests)
  set(_cost 0)
  list(FIND _rgbdi_costed_names \"\${_name}\" _index)
  if(_index GREATER -1)
    list(GET _rgbdi_costed_values \${_index} _cost)
  endif()
  math(EXPR _cost \"${_serial_base} + \${_cost}\")
  set_tests_properties(\"\${_name}\" PROPERTIES COST \${_cost})
endforeach()
")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${_costs_file}")
endfunction()
