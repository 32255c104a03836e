# The options a consumer project of the tests is configured with, from the build that runs the
# test (CONSUMER_GENERATOR, CONSUMER_MAKE_PROGRAM, CONSUMER_CXX_COMPILER): shared by
# run_consumer_test.cmake and run_configure_checks.cmake.
function(consumer_configure_options out)
  set(options)
  if(CONSUMER_GENERATOR)
    list(APPEND options -G "${CONSUMER_GENERATOR}")
  endif()
  if(CONSUMER_MAKE_PROGRAM)
    list(APPEND options "-DCMAKE_MAKE_PROGRAM=${CONSUMER_MAKE_PROGRAM}")
  endif()
  if(CONSUMER_CXX_COMPILER)
    list(APPEND options "-DCMAKE_CXX_COMPILER=${CONSUMER_CXX_COMPILER}")
  endif()
  set(${out} ${options} PARENT_SCOPE)
endfunction()
