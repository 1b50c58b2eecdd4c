// [transport] of a device profile: how popcut reaches the device and paces it; the language checks the abort string.
#include <algorithm>
#include <cctype>
#include <cstddef>
#include <string>

#include "language_units.h"
#include "popcut/drivers/device.h"

namespace popcut::drivers {
namespace {

// "vvvv:pppp" in hex, as lsusb prints USB ids.
bool usb_id_text(const std::string& s) {
  if (s.size() != 9 || s[4] != ':') return false;
  for (std::size_t i = 0; i < 9; ++i) {
    if (i != 4 && !std::isxdigit(static_cast<unsigned char>(s[i]))) return false;
  }
  return true;
}

// The drain queries a profile may name (esc_e is the error query's, below), and the error
// queries: the names are kDrainQueryNames'.
constexpr auto kProfileDrainQueries =
    enum_names<DrainQuery>({{DrainQuery::none, kDrainQueryNames.name(DrainQuery::none)},
                            {DrainQuery::esc_b, kDrainQueryNames.name(DrainQuery::esc_b)},
                            {DrainQuery::esc_o, kDrainQueryNames.name(DrainQuery::esc_o)},
                            {DrainQuery::esc_enq, kDrainQueryNames.name(DrainQuery::esc_enq)}});
constexpr auto kProfileErrorQueries =
    enum_names<DrainQuery>({{DrainQuery::none, kDrainQueryNames.name(DrainQuery::none)},
                            {DrainQuery::esc_e, kDrainQueryNames.name(DrainQuery::esc_e)}});

void read_usb_ids(TomlSection& t, TransportDefaults& out) {
  const toml::array* ids = t.array("usb_ids");
  if (!ids) return;
  for (const toml::node& n : *ids) {
    const std::string id = n.value<std::string>().value_or("");
    if (!usb_id_text(id)) t.fail("usb_ids", "\"" + id + "\" is not a USB id like \"0b4d:110a\" (hex vendor:product)");
    std::string lower;
    for (char c : id) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    out.usb_ids.push_back(lower);
  }
}

// The drain queries `language` has, as a profile names them: "\"esc_b\" or \"esc_o\""; with
// `idle_only`, those whose answers say whether the device has executed everything.
std::string queries_of(const LanguageUnit& language, bool idle_only = false) {
  std::string list;
  for (const DrainQuery q : {DrainQuery::esc_b, DrainQuery::esc_o, DrainQuery::esc_enq}) {
    if (idle_only && q == DrainQuery::esc_b) continue;
    if (language.host().query_bytes(q).empty()) continue;
    list += (list.empty() ? "\"" : " or \"") + std::string(kDrainQueryNames.name(q)) + "\"";
  }
  return list;
}

// The drain and error queries must be the language's, and the pacing must have the answers it
// reads: ESC.B's free bytes, or idle/busy answers for status flow.
void check_queries(const TomlSection& t, const LanguageUnit& language, const TransportDefaults& out) {
  const HostProtocol& host = language.host();
  const std::string lang = "[device] language \"" + std::string(language.section) + "\"";
  if (out.flow == FlowControl::esc_b && host.query_bytes(DrainQuery::esc_b).empty()) {
    t.fail("flow_control", "\"esc_b\" asks ESC.B for free buffer space, which " + lang +
                               " devices do not answer: use \"status\" (paced by the motion model and their " +
                               queries_of(language) + " answers), or a hardware handshake");
  }
  if (out.drain_query != DrainQuery::none && host.query_bytes(out.drain_query).empty()) {
    t.fail("drain_query", "\"" + std::string(kDrainQueryNames.name(out.drain_query)) + "\" is not a query of " + lang +
                              ", whose devices answer " + queries_of(language));
  }
  if (out.flow == FlowControl::status && out.drain_query != DrainQuery::esc_o &&
      out.drain_query != DrainQuery::esc_enq) {
    t.fail("flow_control",
           "\"status\" paces by the device's ready/busy answers: it needs drain_query " + queries_of(language, true) +
               " (one that says whether the device has executed everything)" +
               (out.drain_query == DrainQuery::esc_b ? ", not \"esc_b\" (use flow_control \"esc_b\")" : ""));
  }
  if (out.error_query && host.query_bytes(DrainQuery::esc_e).empty()) {
    t.fail("error_query", "\"esc_e\" is not a query of " + lang + ": its devices report no I/O error");
  }
}

}  // namespace

void read_transport_section(TomlSection& t, const LanguageUnit& language, TransportDefaults& out) {
  out.uri = t.text("default", "");  // no guess: `popcut cut` asks for --device
  if (!out.uri.empty()) {
    // Checked here so a bad default is blamed on the profile, not on a --device flag never given.
    DeviceAddress address;
    const TransportStatus parsed = parse_device(out.uri, address);
    if (!parsed.ok()) t.fail("default", parsed.message);
  }
  out.baud = t.integer("baud", 9600, 300, 4000000);
  out.flow = t.choice("flow_control", FlowControl::none, kFlowControlNames);
  out.buffer_bytes = static_cast<std::size_t>(t.integer("buffer_bytes", 1024, 64, 1 << 26));
  // At least a native UART's FIFO: 0 would claim bytes still in the UART as received.
  out.adapter_fifo_bytes = static_cast<std::size_t>(t.integer("adapter_fifo_bytes", 4096, 16, 1 << 20));
  out.timeout_ms = t.integer("timeout_ms", 5000, 10, 600000);
  out.hold_timeout_ms = t.integer("hold_timeout_ms", 120000, 10, 3600000);
  out.pace_margin_percent = t.integer("pace_margin_percent", 25, 0, 1000);
  out.pace_margin_calibrated_percent =
      t.integer("pace_margin_calibrated_percent", std::min(10, out.pace_margin_percent), 0, 1000);
  // A measured pace is known at least as well as a guessed one.
  if (out.pace_margin_calibrated_percent > out.pace_margin_percent) {
    t.fail("pace_margin_calibrated_percent", "must not exceed pace_margin_percent (" +
                                                 std::to_string(out.pace_margin_percent) +
                                                 "): a measured pace is known at least as well as the profile's own");
  }
  out.data_bits = t.integer("data_bits", 8, 5, 8);
  out.parity = t.choice("parity", Parity::none, kParityNames);
  out.stop_bits = t.integer("stop_bits", 1, 1, 2);
  out.drain_query =
      t.choice("drain_query", out.flow == FlowControl::esc_b ? DrainQuery::esc_b : language.host().default_query(),
               kProfileDrainQueries);
  out.error_query = t.choice("error_query", DrainQuery::none, kProfileErrorQueries) == DrainQuery::esc_e;
  check_queries(t, language, out);
  out.abort = t.text("abort", "", 64);
  language.check_abort(t, out.abort);
  // An abort is there to stop the device at once, which HP-style devices do by discarding their
  // buffer (ESC.K): what was received but not cut is then gone. Assuming so unless the profile
  // says otherwise never skips a stroke on resume; the opposite guess would leave strokes uncut.
  out.abort_discards_buffer = t.boolean("abort_discards_buffer", !out.abort.empty());
  if (out.abort_discards_buffer && out.abort.empty()) {
    t.fail("abort_discards_buffer",
           "true needs an abort sequence that makes the device discard its buffer (e.g. abort = \"\\u001b.K\")");
  }
  read_usb_ids(t, out);
  out.usb_chunk_bytes = static_cast<std::size_t>(t.integer("usb_chunk_bytes", 4096, 8, 1 << 20));
}

}  // namespace popcut::drivers
