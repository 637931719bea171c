# plucker_add_library(NAME <layer> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...] [NOT_INSTALLED])
#   Creates target plucker_<layer> (alias plucker::<layer>), installed and exported.
#   Headers are included as "plucker/<layer>/x.h" from src/.
#   NOT_INSTALLED: test and benchmark scaffolding (verify, testing): a static library for the
#   tests, benchmarks and the CLI, neither installed nor exported (an installed library that
#   linked it would make the export fail, so the package cannot come to depend on it).
function(plucker_add_library)
  cmake_parse_arguments(ARG "NOT_INSTALLED" "NAME" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target plucker_${ARG_NAME})
  if(ARG_NOT_INSTALLED)
    add_library(${target} STATIC ${ARG_SOURCES})
  else()
    add_library(${target} ${ARG_SOURCES})
  endif()
  add_library(plucker::${ARG_NAME} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${ARG_NAME} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  if(ARG_NOT_INSTALLED)
    return()
  endif()
  install(TARGETS ${target} EXPORT pluckerTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  file(GLOB headers "${CMAKE_CURRENT_SOURCE_DIR}/*.h")
  # Test scaffolding that lives next to the code it tests is not installed either.
  list(FILTER headers EXCLUDE REGEX "(_test_utils|fuzz_util|_internal)\\.h$")
  install(FILES ${headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/plucker/${ARG_NAME})
endfunction()

# plucker_add_test(NAME <name> SOURCES ... DEPS ...)
#   A GoogleTest executable registered with CTest. PLUCKER_SHARED_DATA_DIR is passed as a define.
function(plucker_add_test)
  if(NOT PLUCKER_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_compile_options(${ARG_NAME} PRIVATE -Wall -Wextra)
  target_compile_definitions(${ARG_NAME} PRIVATE
    PLUCKER_SHARED_DATA_DIR="${PLUCKER_SHARED_DATA_DIR}")
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main GTest::gmock)
  gtest_discover_tests(${ARG_NAME} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 900)
endfunction()

# plucker_add_layer(NAME <layer> [PUBLIC_DEPS ...] [PRIVATE_DEPS ...] [TEST_DEPS ...]
#                   [NOT_INSTALLED])
#   The library is every *.cc of the folder except *_test.cc, *_fuzz.cc and *_benchmark.cc;
#   every *_test.cc becomes its own test executable <layer>_<file> linked with the layer,
#   plucker::verify and TEST_DEPS. New files are picked up at the next build (CONFIGURE_DEPENDS).
#   NOT_INSTALLED: see plucker_add_library (scaffolding layers: verify, testing).
function(plucker_add_layer)
  cmake_parse_arguments(ARG "NOT_INSTALLED" "NAME" "PUBLIC_DEPS;PRIVATE_DEPS;TEST_DEPS" ${ARGN})
  set(not_installed)
  if(ARG_NOT_INSTALLED)
    set(not_installed NOT_INSTALLED)
  endif()
  file(GLOB sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*.cc")
  list(FILTER sources EXCLUDE REGEX "_(test|fuzz|benchmark)\\.cc$")
  if(NOT sources)
    # A layer with no code yet: an interface target so that dependants still configure.
    add_library(plucker_${ARG_NAME} INTERFACE)
    add_library(plucker::${ARG_NAME} ALIAS plucker_${ARG_NAME})
    target_link_libraries(plucker_${ARG_NAME} INTERFACE ${ARG_PUBLIC_DEPS})
    set_target_properties(plucker_${ARG_NAME} PROPERTIES EXPORT_NAME ${ARG_NAME})
    if(NOT ARG_NOT_INSTALLED)
      install(TARGETS plucker_${ARG_NAME} EXPORT pluckerTargets)
    endif()
    return()
  endif()
  plucker_add_library(NAME ${ARG_NAME} SOURCES ${sources} ${not_installed}
    PUBLIC_DEPS ${ARG_PUBLIC_DEPS} PRIVATE_DEPS ${ARG_PRIVATE_DEPS})
  file(GLOB tests CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*_test.cc")
  foreach(test_source ${tests})
    get_filename_component(stem ${test_source} NAME_WE)
    plucker_add_test(NAME ${ARG_NAME}_${stem} SOURCES ${test_source}
      DEPS plucker::${ARG_NAME} plucker::verify ${ARG_TEST_DEPS})
  endforeach()
endfunction()
