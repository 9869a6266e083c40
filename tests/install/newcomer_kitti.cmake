# SPDX-License-Identifier: BSD-3-Clause
# A newcomer's first run, from an install prefix: installs the build into a
# scratch prefix outside the build tree (as scripts/check-install.sh does),
# then, from an empty working folder,
#   PREFIX/bin/emslam-mapper -c kitti DATA/kitti-odometry --out OUT
# maps the shared KITTI excerpt with the installed kitti.ini found by its
# name, without a rawlog step, the ground truth taken from the folder. Its
# summary.json must name the installed config and hold the numbers the KITTI
# tests assert (tests/apps/MapperApp_unittest.cpp, kitti06*).
# Arguments: -DBUILD=<build dir> -DDATA=<test data folder>.
if(DEFINED ENV{EMSLAM_TEST_DATA})
    set(DATA "$ENV{EMSLAM_TEST_DATA}")
endif()
if(NOT IS_DIRECTORY "${DATA}/kitti-odometry/sequences/06")
    message("SKIPPED: test data '${DATA}/kitti-odometry' not found (set EMSLAM_TEST_DATA)")
    return()
endif()
set(_tmp "$ENV{TMPDIR}")
if(NOT _tmp)
    set(_tmp "/tmp")
endif()
string(RANDOM LENGTH 8 _tag)
set(_scratch "${_tmp}/emslam-newcomer-${_tag}")
set(_prefix "${_scratch}/prefix")
file(MAKE_DIRECTORY "${_scratch}/work")

function(fail what)
    file(REMOVE_RECURSE "${_scratch}")
    message(FATAL_ERROR "${what}")
endfunction()

execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD}" --prefix "${_prefix}"
    RESULT_VARIABLE _rc OUTPUT_QUIET ERROR_VARIABLE _err)
if(NOT _rc EQUAL 0)
    fail("cmake --install failed (${_rc}): ${_err}")
endif()

execute_process(
    COMMAND "${_prefix}/bin/emslam-mapper" -c kitti "${DATA}/kitti-odometry" --out out -q
    WORKING_DIRECTORY "${_scratch}/work"
    RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _err)
message("${_out}${_err}")
if(NOT _rc EQUAL 0)
    fail("the installed emslam-mapper failed (exit ${_rc})")
endif()
file(READ "${_scratch}/work/out/summary.json" _summary)

string(JSON _config GET "${_summary}" config)
if(NOT _config STREQUAL "${_prefix}/share/emslam/config/mapper/kitti.ini")
    fail("config '${_config}' is not the installed kitti.ini")
endif()
string(JSON _matched GET "${_summary}" slam_vs_gt matched_poses)
string(JSON _ego_ate GET "${_summary}" egomotion_vs_gt ate_rmse_m)
string(JSON _ego_end GET "${_summary}" egomotion_vs_gt end_error_m)
string(JSON _slam_ate GET "${_summary}" slam_vs_gt ate_rmse_m)
string(JSON _slam_end GET "${_summary}" slam_vs_gt end_error_m)
message("ATE egomotion ${_ego_ate} m, SLAM ${_slam_ate} m; "
        "end error egomotion ${_ego_end} m, SLAM ${_slam_end} m; ${_matched} poses matched")
# As MapperApp.kitti06RectificationDoesNoHarm: measured ATE 0.095 m, end
# error 0.36 m; the rectification does no harm.
if(NOT _matched EQUAL 51)
    fail("${_matched} poses matched the ground truth, not 51")
endif()
if(NOT _ego_ate LESS 0.12 OR NOT _ego_end LESS 0.45)
    fail("egomotion ATE ${_ego_ate} m (limit 0.12) or end error ${_ego_end} m (limit 0.45)")
endif()
if(_slam_ate GREATER _ego_ate OR _slam_end GREATER _ego_end)
    fail("SLAM (ATE ${_slam_ate} m, end ${_slam_end} m) worse than the egomotion")
endif()
file(REMOVE_RECURSE "${_scratch}")
