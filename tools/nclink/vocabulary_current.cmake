# docs/vocabulary.md is generated from the validator's tables: fail when the
# committed file differs from what `nclink vocabulary` prints now.
# Regenerate with: build/bin/nclink vocabulary > docs/vocabulary.md
execute_process(COMMAND ${CLI} vocabulary OUTPUT_FILE ${OUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nclink vocabulary failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT} ${DOC} RESULT_VARIABLE differ)
if(NOT differ EQUAL 0)
  message(FATAL_ERROR "${DOC} is out of date: run `nclink vocabulary > docs/vocabulary.md` (generated copy: ${OUT})")
endif()
