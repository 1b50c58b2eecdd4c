// The language units' registry rows and the profile section readers that live beside their owners.
#pragma once

#include "popcut/drivers/language.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/toml_section.h"

namespace popcut::drivers {

extern const LanguageUnit kHpglLanguage;  // hpgl_language.cpp
extern const LanguageUnit kGpglLanguage;  // gpgl_language.cpp

// [transport] (transport_profile.cpp); the language checks the abort string.
void read_transport_section(TomlSection& section, const LanguageUnit& language, TransportDefaults& transport);

}  // namespace popcut::drivers
