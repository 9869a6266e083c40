# SPDX-License-Identifier: BSD-3-Clause
# Fails when any C++ source under libs/, apps/, tests/, benchmarks/ or fuzz/ is not clang-format
# clean.
file(GLOB_RECURSE _files
    ${ROOT}/libs/*.h ${ROOT}/libs/*.cpp ${ROOT}/apps/*.cpp
    ${ROOT}/tests/*.h ${ROOT}/tests/*.cpp ${ROOT}/benchmarks/*.cpp ${ROOT}/fuzz/*.h ${ROOT}/fuzz/*.cpp)
execute_process(
    COMMAND ${CLANG_FORMAT} --dry-run -Werror --style=file ${_files}
    WORKING_DIRECTORY ${ROOT}
    RESULT_VARIABLE _rc
    ERROR_VARIABLE _err)
if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "clang-format differences (run clang-format -i on these files):\n${_err}")
endif()
list(LENGTH _files _n)
message(STATUS "${_n} files are clang-format clean")
