# cmake -DINPUT=x.spv -DOUTPUT=x.cpp -DSYMBOL=name -P spirv_to_cpp.cmake
# Writes the SPIR-V words of INPUT as a C++ array (SPIR-V files are little-endian words).
file(READ ${INPUT} hex HEX)
string(LENGTH "${hex}" chars)
math(EXPR rest "${chars} % 8")
if(chars EQUAL 0 OR NOT rest EQUAL 0)
  message(FATAL_ERROR "${INPUT} is not a SPIR-V binary (${chars} hex digits)")
endif()
math(EXPR words "${chars} / 8")
string(REGEX REPLACE "(..)(..)(..)(..)" "0x\\4\\3\\2\\1u," body "${hex}")
string(REGEX REPLACE "(([^,]*,){8})" "\\1\n    " body "${body}")
file(WRITE ${OUTPUT}.tmp
"// Generated from ${INPUT} by spirv_to_cpp.cmake: do not edit.
#include <cstddef>
#include <cstdint>
namespace frnn::spirv {
extern const std::uint32_t ${SYMBOL}[];
extern const std::size_t ${SYMBOL}_words;
const std::uint32_t ${SYMBOL}[] = {
    ${body}
};
const std::size_t ${SYMBOL}_words = ${words};
}  // namespace frnn::spirv
")
file(RENAME ${OUTPUT}.tmp ${OUTPUT})
