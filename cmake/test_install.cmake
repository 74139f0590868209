# ctest install_example: cmake --install the build into a temporary prefix, then configure, build
# and run examples/core_consumer against it (find_package(gmslab) -> gmslab::core).
# -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... [-DPYTHON=python3: also import the installed module]
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix"
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
foreach(f lib/cmake/gmslab/gmslabConfig.cmake lib/libcore.a include/gmslab/core/friction/model.hpp
          share/gmslab/presets/fig2a_presliding.json)
  if(NOT EXISTS "${WORK_DIR}/prefix/${f}")
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/core_consumer" -B "${WORK_DIR}/build"
                        -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the example against the installed package failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build "${WORK_DIR}/build" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the example failed")
endif()
execute_process(COMMAND "${WORK_DIR}/build/core_consumer" "${WORK_DIR}/prefix/share/gmslab/presets/fig2a_presliding.json"
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the example failed (${rc})")
endif()
if(PYTHON)  # the installed Python package imports and simulates an installed preset
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${WORK_DIR}/prefix/lib/python3/dist-packages
                          ${PYTHON} -c "import gmslab, sys; tr = gmslab.simulate(sys.argv[1]); assert len(tr) > 1; print(gmslab.__file__)"
                          "${WORK_DIR}/prefix/share/gmslab/presets/fig2a_presliding.json"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE where)
  if(NOT rc EQUAL 0 OR NOT where MATCHES "prefix/lib/python3/dist-packages/gmslab")
    message(FATAL_ERROR "the installed Python package failed (${rc}): ${where}")
  endif()
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
