# SPDX-License-Identifier: BSD-3-Clause
# Configures, builds and runs the ThreadSanitizer project (see CMakeLists.txt).
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC} -B ${BIN} -DCMAKE_BUILD_TYPE=RelWithDebInfo
    RESULT_VARIABLE rc)
if(rc)
    message(FATAL_ERROR "tsan: configure failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BIN} -j2 RESULT_VARIABLE rc)
if(rc)
    message(FATAL_ERROR "tsan: build failed")
endif()
# halt_on_error: the first race report makes the run fail.
set(ENV{TSAN_OPTIONS} "halt_on_error=1 second_deadlock_stack=1")
execute_process(COMMAND ${BIN}/tsan_anytime RESULT_VARIABLE rc)
if(rc)
    message(FATAL_ERROR "tsan: the AnyTime or split-move test failed or ThreadSanitizer reported (exit ${rc})")
endif()
execute_process(COMMAND ${BIN}/tsan_sparse_front_end RESULT_VARIABLE rc)
if(rc)
    message(FATAL_ERROR
        "tsan: the sparse front-end test failed or ThreadSanitizer reported (exit ${rc})")
endif()
execute_process(COMMAND ${BIN}/tsan_loop_closing RESULT_VARIABLE rc)
if(rc)
    message(FATAL_ERROR
        "tsan: the loop-closing test failed or ThreadSanitizer reported (exit ${rc})")
endif()
