# hilrig_proto_tags(TARGET name OUTPUT header IMPORT_DIR dir PROTOS a.proto ...): an INTERFACE
# library `name` whose users include OUTPUT (e.g. "proto/hil_link_tags.h"), a header of the protos'
# field numbers and enum values (cmake/proto_tags_header.cmake), generated at build time with
# Debian's nanopb generator. Code that reads and writes the messages by hand (dut_fw, on the host
# and on the target) takes its numbers from it, never from literals kept equal by tests.
function(hilrig_proto_tags)
  cmake_parse_arguments(arg "" "TARGET;OUTPUT;IMPORT_DIR" "PROTOS" ${ARGN})
  find_program(HILRIG_NANOPB_GENERATOR nanopb_generator.py)
  if(NOT HILRIG_NANOPB_GENERATOR)
    message(FATAL_ERROR "nanopb_generator.py not found (Debian package nanopb; scripts/setup "
                        "installs it)")
  endif()
  set(work_dir ${CMAKE_CURRENT_BINARY_DIR}/nanopb)
  set(headers "")
  set(names "")
  foreach(proto IN LISTS arg_PROTOS)
    get_filename_component(name ${proto} NAME_WE)
    list(APPEND headers ${work_dir}/${name}.pb.h)
    list(APPEND names ${name}.proto)
  endforeach()
  list(JOIN headers "," header_list)
  list(JOIN names " and " name_text)
  set(output ${CMAKE_BINARY_DIR}/generated/${arg_OUTPUT})
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${work_dir}
    COMMAND ${HILRIG_NANOPB_GENERATOR} -q -D ${work_dir} -I ${arg_IMPORT_DIR} ${arg_PROTOS}
    COMMAND ${CMAKE_COMMAND} -DINPUTS=${header_list} -DOUTPUT=${output} "-DSOURCES=${name_text}"
            -P ${HILRIG_PROTO_TAGS_SCRIPT}
    DEPENDS ${arg_PROTOS} ${HILRIG_PROTO_TAGS_SCRIPT}
    COMMENT "Generating ${arg_OUTPUT}"
    VERBATIM)
  add_custom_target(${arg_TARGET}_header DEPENDS ${output})
  add_library(${arg_TARGET} INTERFACE)
  target_include_directories(${arg_TARGET} INTERFACE ${CMAKE_BINARY_DIR}/generated)
  add_dependencies(${arg_TARGET} ${arg_TARGET}_header)
endfunction()

set(HILRIG_PROTO_TAGS_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/proto_tags_header.cmake)
