# The build's commit for `hrpp --version` and the provenance its reports and images record
# (host/app/provenance.h): cmake/write_build_commit.cmake asks git at every build, so the name
# never goes stale, and writes the source only when it changes. Included after host/, whose
# `hrpp` executable links the library.
set(hrpp_commit_source "${CMAKE_BINARY_DIR}/generated/build_commit.cpp")
set(hrpp_commit_command "${CMAKE_COMMAND}" "-DSOURCE_DIR=${PROJECT_SOURCE_DIR}"
    "-DOUT=${hrpp_commit_source}" -P "${PROJECT_SOURCE_DIR}/cmake/write_build_commit.cmake")
execute_process(COMMAND ${hrpp_commit_command})  # so that the source exists from configure on
add_custom_target(hrpp_build_commit COMMAND ${hrpp_commit_command}
                  BYPRODUCTS "${hrpp_commit_source}" VERBATIM)
add_library(hrpp_provenance STATIC "${PROJECT_SOURCE_DIR}/host/app/provenance.cpp"
                                   "${hrpp_commit_source}")
add_dependencies(hrpp_provenance hrpp_build_commit)
target_link_libraries(hrpp_provenance PUBLIC hrpp_render nlohmann_json::nlohmann_json)
target_link_libraries(hrpp PRIVATE hrpp_provenance)
