#pragma once
// debris_peridem's reference: every key its input reader accepts (peridem_input.cpp and the sections it
// shares: stages) and the columns of every table it writes. `debris_peridem --keys` and `--columns` print
// them; scenarios/peridem/README.md holds the same tables. The descriptions of a PeriDEM material and of the
// contact settings are shared with debris_restitution (scenarios/restitution/restitution_keys.cpp).
#include <string>
#include <vector>

#include "core/io/key_reference.hpp"

namespace debris {

const KeyReference& peridem_keys();
std::vector<ColumnTable> peridem_output_columns();

/// thermo.csv: `<wall>` columns once per wall, `<grain>` columns once per grain in runs with few grains
/// ("per grain"); z components only in 3D runs.
const ColumnTable& peridem_thermo_table();

/// The keys read_pd_material() reads under `prefix` ("materials.<name>"), and `prefix` itself.
void document_pd_material(KeyReference& ref, const std::string& prefix);

/// One of the contact settings of PdContactSettings (contact_radius_factor, restitution, damping_factor,
/// friction, stiffness_factor, damping_onset_factor) or the damping choice (`damping`), described at
/// `path` with its kind, range, meaning and equation; the caller adds the default.
KeyDoc& document_pd_contact_setting(KeyReference& ref, const std::string& path, const std::string& setting);

}  // namespace debris
