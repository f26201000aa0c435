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
function(rgbdi_add_test NAME)
  cmake_parse_arguments(ARG "SERIAL" "" "DEPS;SOURCES" ${ARGN})
  add_executable(${NAME} ${ARG_SOURCES})
  target_compile_options(${NAME} PRIVATE ${RGBDI_WARNINGS})
  target_link_libraries(${NAME} PRIVATE ${ARG_DEPS} rgbdi_testing GTest::gtest GTest::gtest_main)
  gtest_discover_tests(${NAME} DISCOVERY_TIMEOUT 60
    PROPERTIES ENVIRONMENT "RGBDI_SHARED_DATA=${RGBDI_SHARED_DATA_DIR};RGBDI_BIN_DIR=${CMAKE_BINARY_DIR}/bin")
  if(ARG_SERIAL)
    # Not through PROPERTIES above: its ENVIRONMENT list is flattened into the property pairs.
    # A ctest include file run after the discovered tests' one marks every test of NAME.
    set(_serial_file "${CMAKE_CURRENT_BINARY_DIR}/${NAME}_run_serial.cmake")
    file(WRITE "${_serial_file}"
      "if(${NAME}_TESTS)\n  set_tests_properties(\${${NAME}_TESTS} PROPERTIES RUN_SERIAL TRUE)\nendif()\n")
    set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${_serial_file}")
  endif()
endfunction()
