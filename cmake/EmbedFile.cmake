# SPDX-License-Identifier: Apache-2.0
# Writes a file's bytes into a C++ header as an array, so that a program carries the file in
# itself (the guide's page: serve/guide_page.html).
# Usage: cmake -DINPUT=FILE -DOUTPUT=HEADER -DNAME=kName -DNAMESPACE=ns -P EmbedFile.cmake
# The header declares `inline constexpr unsigned char NAME[]` and `NAMESize` (the file's size,
# no terminating zero) in namespace NAMESPACE.
file(READ "${INPUT}" hex HEX)
string(LENGTH "${hex}" hex_length)
math(EXPR size "${hex_length} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
string(REGEX REPLACE "((0x[0-9a-f][0-9a-f],){24})" "\\1\n" bytes "${bytes}")
get_filename_component(input_name "${INPUT}" NAME)
file(WRITE "${OUTPUT}.tmp"
"// SPDX-License-Identifier: Apache-2.0
// Generated from ${input_name} by cmake/EmbedFile.cmake at build time: edit the source file.
#pragma once
#include <cstddef>
namespace ${NAMESPACE} {
inline constexpr unsigned char ${NAME}[] = {
${bytes}
0x00};
inline constexpr std::size_t ${NAME}Size = ${size};
}  // namespace ${NAMESPACE}
")
# Only a changed header is replaced, so that an unchanged page recompiles nothing.
execute_process(COMMAND "${CMAKE_COMMAND}" -E copy_if_different "${OUTPUT}.tmp" "${OUTPUT}")
file(REMOVE "${OUTPUT}.tmp")
