// Any text given to the NC read-back parser either reads into moves or fails
// with a DataError at program line:column — never a crash or undefined
// behaviour.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/common/error.h"
#include "core/machine/program_reader.h"
#include "machine/test_machines.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bliskrun::MachineDefinition machine = bliskrun::test::table_table_ac();
  const std::string text(reinterpret_cast<const char*>(data), size);
  bliskrun::ProgramReadOptions options;
  options.file_name = "fuzz.nc";
  options.tcp = size > 0 && (data[0] & 1);
  try {
    bliskrun::read_program(text, machine, options);
  } catch (const bliskrun::DataError& e) {
    if (std::string(e.what()).rfind("fuzz.nc:", 0) != 0) __builtin_trap();
  }
  return 0;
}
