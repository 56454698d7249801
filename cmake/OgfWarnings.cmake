# Compiler warnings and sanitizer options shared by every ogf target.
add_library(ogf_warnings INTERFACE)
add_library(ogf::warnings ALIAS ogf_warnings)
target_compile_options(ogf_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Wunused
  -Woverloaded-virtual -Wconversion -Wsign-conversion -Wdouble-promotion
  # Not -Wnull-dereference: at -O2 it fires inside Boost.Asio's inlined scheduler, not in our code.
  -Wformat=2 -Wimplicit-fallthrough
  $<$<BOOL:${OGF_WERROR}>:-Werror>)

if(OGF_SANITIZE)
  # ASan + UBSan for the whole build (tests, tools, daemons); UBSan aborts on the first finding.
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=address,undefined)
endif()
