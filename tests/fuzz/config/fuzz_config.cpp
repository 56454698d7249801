// Fuzzes the daemons' configuration parsers with any text: the first byte picks the mapping programs'
// options (parseMapperOptions, then MapperOptions::validate, then --print-config's YAML of what was read,
// which must read back) or ogf-driver's (parseDriverConfig, then validate without a calibration file, which
// would read the disk); the rest is the YAML. A file either loads or is refused with an error naming it; no
// exception may escape, as one would end the program at start-up.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "driver_config.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string yaml(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] & 1) {
    ogf::mapper_daemon::MapperOptions options;
    if (ogf::mapper_daemon::parseMapperOptions(yaml, "fuzz.yaml", options)) {
      (void)options.validate();
      const std::string printed = ogf::mapper_daemon::mapperConfigYaml(options);
      ogf::mapper_daemon::MapperOptions again;
      if (!ogf::mapper_daemon::parseMapperOptions(printed, "printed.yaml", again)) std::abort();
      if (ogf::mapper_daemon::mapperConfigYaml(again) != printed) std::abort();
    }
  } else {
    auto config = ogf::driver::parseDriverConfig(yaml, "fuzz.yaml", ogf::driver::DriverConfig{});
    if (config) {
      config->calibration.clear();
      (void)ogf::driver::validate(*config);
    }
  }
  return 0;
}
