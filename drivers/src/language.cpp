// The registry of cutter languages: the profile's `language` picks the row its encoder and reader come from.
#include "popcut/drivers/language.h"

#include <array>

#include "language_units.h"
#include "popcut/error.h"

namespace popcut::drivers {
namespace {

// One row per value of CutterLanguage, in kCutterLanguageNames order.
const std::array<const LanguageUnit*, 2> kUnits = {&kHpglLanguage, &kGpglLanguage};

}  // namespace

std::span<const LanguageUnit* const> language_units() { return kUnits; }

const LanguageUnit& language_unit(CutterLanguage language) {
  for (const LanguageUnit* unit : kUnits) {
    if (unit->language == language) return *unit;
  }
  throw Error(ErrorCode::internal, "", "language",
              "no language unit for '" + std::string(kCutterLanguageNames.name(language)) + "'");
}

std::unique_ptr<JobEncoder> make_encoder(const DeviceProfile& profile) {
  return language_unit(profile.language).make_encoder(profile);
}

EncodedJob encode_for_device(const StrokePlan& plan, const DeviceProfile& profile, std::size_t from_stroke) {
  return make_encoder(profile)->encode(plan, profile.tools, from_stroke);
}

std::unique_ptr<DeviceReader> make_reader(const DeviceProfile& profile) {
  return language_unit(profile.language).make_reader();
}

}  // namespace popcut::drivers
