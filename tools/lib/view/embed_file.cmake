# cmake -DINPUT=file -DOUTPUT=file.cpp -P embed_file.cmake: writes ogf::view::indexHtml() returning INPUT's
# bytes.
file(READ "${INPUT}" hex HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
string(LENGTH "${hex}" hex_length)
math(EXPR length "${hex_length} / 2")
file(WRITE "${OUTPUT}.tmp"
  "// Generated from ${INPUT} by embed_file.cmake.\n"
  "#include \"ogf/view/web_page.hpp\"\n"
  "namespace ogf::view {\n"
  "namespace { constexpr unsigned char kBytes[] = {${bytes}0}; }\n"
  "std::string_view indexHtml() { return {reinterpret_cast<const char*>(kBytes), ${length}}; }\n"
  "}  // namespace ogf::view\n")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
