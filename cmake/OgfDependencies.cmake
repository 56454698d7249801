# Every external dependency, each a Debian 12 package (scripts/install-deps.sh installs them).
find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)             # libeigen3-dev
find_package(Boost 1.74 REQUIRED)                       # libboost-dev (Asio is header-only)
find_package(spdlog REQUIRED)                           # libspdlog-dev (external fmt)
find_package(yaml-cpp REQUIRED)                         # libyaml-cpp-dev
find_package(CLI11 REQUIRED)                            # libcli11-dev
find_package(PkgConfig REQUIRED)
pkg_check_modules(PCAP REQUIRED IMPORTED_TARGET libpcap)  # libpcap-dev
pkg_check_modules(SODIUM REQUIRED IMPORTED_TARGET libsodium)  # libsodium-dev (map command MACs)
find_package(SQLite3 REQUIRED)                          # libsqlite3-dev (rosbag2 bags)

if(TARGET yaml-cpp AND NOT TARGET yaml-cpp::yaml-cpp)
  add_library(yaml-cpp::yaml-cpp ALIAS yaml-cpp)
endif()

if(OGF_BUILD_TESTS)
  find_package(GTest REQUIRED)                          # libgtest-dev
endif()
if(OGF_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)                      # libbenchmark-dev
endif()

# The Python that has Debian's packages (numpy, pytest, Pillow, PyYAML, matplotlib; scripts/install-deps.sh):
# /usr/bin/python3, not whatever python3 comes first on PATH (a pyenv shim, a virtualenv). The Python package
# (python/) is built for it and the Python tests run with it.
find_program(OGF_PYTHON3 NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT OGF_PYTHON3)
  find_package(Python3 COMPONENTS Interpreter REQUIRED)
  set(OGF_PYTHON3 "${Python3_EXECUTABLE}" CACHE FILEPATH "The Python with Debian's packages" FORCE)
endif()
