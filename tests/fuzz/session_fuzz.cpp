// libFuzzer target: window session files (core/io/session_io.hpp) from arbitrary bytes.
//
// parse_json + session_from_json must accept the bytes or throw InputError; an accepted session
// must survive a save/load round trip unchanged (what the window saves, it restores).
#include <cstdint>
#include <string>

#include "core/error.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/session_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gmslab;
  const std::string text(reinterpret_cast<const char*>(data), size);
  Session s;
  try {
    s = session_from_json(parse_json(text, "fuzz.session.json"), "fuzz.session.json");
  } catch (const InputError&) {
    return 0;
  }
  const std::string saved = to_json(s).dump(2);
  if (!(session_from_json(parse_json(saved, "saved.json"), "saved.json") == s)) __builtin_trap();
  return 0;
}
