# `envshadow reference` and `envshadow compare` end to end (ctest runs: cmake -DENVSHADOW=... -DWORK=... -P):
# a white-furnace render, compare of identical files, and the one-line exit-3 errors.
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
file(WRITE "${WORK}/furnace.json" [[
{"environment": "builtin:constant",
 "camera": {"position": [0, 0.5, 3], "target": [0, 0, 0], "fov": 45},
 "objects": [{"name": "ball", "mesh": {"type": "sphere", "radius": 1}, "material": {"diffuse": 1.0}}]}
]])

function(run expected_rc)
  execute_process(COMMAND "${ENVSHADOW}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL expected_rc)
    message(FATAL_ERROR "envshadow ${ARGN}: exit ${rc}, expected ${expected_rc}\n${out}${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
  set(err "${err}" PARENT_SCOPE)
endfunction()

function(expect_one_line_error pattern)
  string(REGEX MATCHALL "\n" newlines "${err}")
  list(LENGTH newlines lines)
  if(NOT lines EQUAL 1 OR NOT err MATCHES "${pattern}")
    message(FATAL_ERROR "expected one line matching '${pattern}', got:\n${err}")
  endif()
endfunction()

run(0 reference --scene "${WORK}/furnace.json" --width 24 --height 16 --exr "${WORK}/a.exr" --png "${WORK}/a.png")
if(NOT out MATCHES "standard error / value: mean [0-9.]+%, p99 [0-9.]+%" OR NOT EXISTS "${WORK}/a.exr" OR NOT EXISTS "${WORK}/a.png")
  message(FATAL_ERROR "reference did not report its errors or write its files:\n${out}")
endif()

run(0 compare "${WORK}/a.exr" "${WORK}/a.exr" --diff "${WORK}/diff.png")
if(NOT out MATCHES "^rel_rmse=0 psnr=inf pixels=[1-9][0-9]*\n$" OR NOT EXISTS "${WORK}/diff.png")
  message(FATAL_ERROR "identical files: ${out}")
endif()

run(0 reference --scene "${WORK}/furnace.json" --width 20 --height 16 --exr "${WORK}/b.exr")
run(3 compare "${WORK}/a.exr" "${WORK}/b.exr")
expect_one_line_error("images differ in size \\(24x16 and 20x16\\)")

run(3 compare "${WORK}/a.exr" "${WORK}/missing.exr")
expect_one_line_error("missing.exr")

file(WRITE "${WORK}/corrupt.exr" "not an EXR file")
run(3 compare "${WORK}/corrupt.exr" "${WORK}/a.exr")
expect_one_line_error("corrupt.exr")

run(3 reference --scene "${WORK}/missing.json" --exr "${WORK}/c.exr")
expect_one_line_error("missing.json")
if(EXISTS "${WORK}/c.exr")
  message(FATAL_ERROR "a failed reference left its output behind")
endif()
run(2 reference --scene "${WORK}/furnace.json" --exr "${WORK}/c.exr" --error 0)
