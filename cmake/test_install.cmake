# ctest install_example: cmake --install the build into a temporary prefix, then configure, build
# and run examples/core_consumer against it (find_package(gmslab) -> gmslab::core; the consumer sets
# no C++ standard: the target carries it), and run the installed `gmslab sweep` with no PYTHONPATH
# (the executable finds its own Python package under the prefix).
# -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... [-DPYTHON=python3: also the installed module]
# [-DAPP=ON: the executables were built, so bin/gmslab must be installed and run]
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
if(PYTHON AND APP)
  if(NOT EXISTS "${WORK_DIR}/prefix/bin/gmslab")
    message(FATAL_ERROR "not installed: bin/gmslab")
  endif()
  # The installed executable finds the installed package itself: no PYTHONPATH, and not from the
  # source or build tree (the working directory is an empty folder).
  set(gmslab_exe "${WORK_DIR}/prefix/bin/gmslab")
  file(MAKE_DIRECTORY "${WORK_DIR}/run")
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH "${gmslab_exe}" sweep --help
                  WORKING_DIRECTORY "${WORK_DIR}/run" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "usage: gmslab sweep")
    message(FATAL_ERROR "installed gmslab sweep --help failed (${rc}): ${out}${err}")
  endif()
  # A tiny sweep: two points of the installed fig2a preset, one local worker.
  file(WRITE "${WORK_DIR}/run/tiny.json"
       "{\"job\": \"simulate\", \"scenario\": \"${WORK_DIR}/prefix/share/gmslab/presets/fig2a_presliding.json\",\n"
       " \"parameters\": {\"friction.Fs\": {\"values\": [1.0, 1.25]}}}\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH "${gmslab_exe}" sweep tiny.json --out tiny.csv
                          --workers 1
                  WORKING_DIRECTORY "${WORK_DIR}/run" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT EXISTS "${WORK_DIR}/run/tiny.csv")
    message(FATAL_ERROR "installed gmslab sweep failed (${rc}): ${out}${err}")
  endif()
  file(STRINGS "${WORK_DIR}/run/tiny.csv" rows)
  list(LENGTH rows nrows)
  set(nok 0)
  foreach(row IN LISTS rows)
    if(row MATCHES "(^|,)ok(,|$)")
      math(EXPR nok "${nok} + 1")
    endif()
  endforeach()
  if(NOT nrows EQUAL 3 OR NOT nok EQUAL 2)
    message(FATAL_ERROR "installed gmslab sweep: expected a header and 2 ok rows in tiny.csv, got:\n${rows}")
  endif()
  message(STATUS "installed gmslab sweep, no PYTHONPATH: ${nok} points ok")
endif()
file(REMOVE_RECURSE "${WORK_DIR}")
