# libFuzzer targets for the io readers: kitti_bin_fuzz, pcd_fuzz, pose_fuzz, euroc_fuzz,
# segments_fuzz, kalibr_fuzz, png_gray_fuzz.
#
# Enabled with -DPLUCKER_BUILD_FUZZERS=ON and clang. Include this file BEFORE
# add_subdirectory(src/plucker) (the libraries must get coverage instrumentation too), e.g.
#   include(cmake/Fuzzers.cmake)
# or without editing CMakeLists.txt: -DCMAKE_PROJECT_INCLUDE=<repo>/cmake/Fuzzers.cmake
# (scripts/fuzz.sh does this). The same entry points run as the unit test io_fuzz_test.
include_guard(GLOBAL)

if(PLUCKER_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "PLUCKER_BUILD_FUZZERS needs clang (e.g. CXX=clang++-14), not "
                        "${CMAKE_CXX_COMPILER_ID}")
  endif()
  # Every library gets coverage + sanitizers; only the fuzz executables link libFuzzer's main.
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
  set(_plucker_fuzz_dir "${CMAKE_CURRENT_LIST_DIR}/../src/plucker/io")
  foreach(_name kitti_bin pcd pose euroc segments kalibr png_gray)
    add_executable(${_name}_fuzz "${_plucker_fuzz_dir}/${_name}_fuzz.cc")
    target_compile_definitions(${_name}_fuzz PRIVATE PLUCKER_LIBFUZZER)
    target_compile_features(${_name}_fuzz PRIVATE cxx_std_17)
    target_compile_options(${_name}_fuzz PRIVATE -Wall -Wextra)
    target_link_options(${_name}_fuzz PRIVATE -fsanitize=fuzzer)
    target_link_libraries(${_name}_fuzz PRIVATE plucker::io)
  endforeach()
endif()
