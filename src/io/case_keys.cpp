#include "io/case_keys.h"

namespace stickslip {

const std::vector<CaseKey>& case_keys() {
  // clang-format off
  static const std::vector<CaseKey> keys{
    {"", "stickslip", "integer", "", "required", false, "format version"},
    {"", "title", "string", "", "`\"\"`", false, "shown in outputs"},
    {"", "materials", "map name → material", "", "none", false, "materials by name"},
    {"", "meshes", "map name → mesh", "", "none", false, "meshes by name"},
    {"", "bodies", "map name → body", "", "required (≥ 1)", false, "bodies by name"},
    {"", "contacts", "list of contacts", "", "none", false, "the contacts, in order"},
    {"", "excitation", "list of forces", "", "none", false, "the harmonic forces"},
    {"", "static_loads", "list of static loads", "", "none", false, "see below: the loads that press the contacts"},
    {"", "rotation", "map", "", "none", false, "the structure spins: centrifugal load, stress stiffening, spin softening, Campbell diagram"},
    {"", "damping", "map", "", "no damping", false, "Rayleigh damping C = alpha M + beta K"},
    {"", "analysis", "map", "", "required", false, "the harmonic balance and its frequency sweep"},
    {"", "study", "map", "", "none", false, "run one analysis per value of one parameter"},
    {"", "recovery", "map", "", "defaults below", false, "full-model displacements and stresses"},
    {"", "output", "map", "", "defaults below", false, "what is written where"},
    {"materials.NAME", "youngs_modulus", "number > 0", "Pa", "required", true, "Young's modulus E"},
    {"materials.NAME", "poisson_ratio", "number −1 < ν < 0.5", "–", "required", true, "Poisson's ratio ν"},
    {"materials.NAME", "density", "number > 0", "kg/m³", "required", true, "mass density ρ"},
    {"meshes.NAME", "generate", "`two_beam`", "", "–", false, "generate the reference two-beam model"},
    {"meshes.NAME", "arrangement", "`butt` | `lap`", "", "`butt`", false, "how the end blocks meet: tip to tip"},
    {"meshes.NAME", "element", "`C3D8` | `C3D8I` | `C3D20` | `C3D20R`", "", "`C3D8I`", false, "hexahedron type"},
    {"meshes.NAME", "coarse", "bool", "", "`false`", false, "the thesis's mesh: 7×5×1 box + 4×5×4 end block, 240 nodes per beam"},
    {"meshes.NAME", "box", "3 integers ≥ 1", "", "`[25, 5, 8]`", false, "elements of the large box along x, y, z"},
    {"meshes.NAME", "end_block", "3 integers ≥ 1", "", "`[5, 5, 4]`", false, "elements of the end block"},
    {"meshes.NAME", "beam2_box", "3 integers ≥ 1", "", "as `box`", false, "beam 2's own large box: its contact face meshed unlike beam 1's"},
    {"meshes.NAME", "beam2_end_block", "3 integers ≥ 1", "", "as `end_block`", false, "beam 2's own end block"},
    {"meshes.NAME", "beam_length", "number > 0", "m", "`0.25`", false, "L, x extent of the large box"},
    {"meshes.NAME", "width", "number > 0", "m", "`0.05`", false, "W, y extent of both boxes"},
    {"meshes.NAME", "thickness", "number > 0", "m", "`0.03`", false, "T, z extent of the large box"},
    {"meshes.NAME", "end_length", "number > 0", "m", "`0.05`", false, "e, x extent of the end block"},
    {"meshes.NAME", "file", "path", "", "–", false, "a mesh file: Abaqus/CalculiX .inp, Gmsh .msh or ANSYS .cdb"},
    {"meshes.NAME", "format", "`inp` | `msh` | `cdb`", "", "from the extension", false, "the file format"},
    {"meshes.NAME", "hexahedron8", "`C3D8` | `C3D8I`", "", "`C3D8I`", false, ".msh only: element for 8-node hexahedra"},
    {"meshes.NAME", "hexahedron20", "`C3D20` | `C3D20R`", "", "`C3D20`", false, ".msh only: element for 20-node hexahedra"},
    {"bodies.NAME", "mesh", "mesh name", "", "required (unless `reduced`)", false, "the mesh the body is cut from"},
    {"bodies.NAME", "element_set", "string", "", "whole mesh", false, "the elements of the body"},
    {"bodies.NAME", "material", "material name", "", "the mesh file's", false, "the body's material"},
    {"bodies.NAME", "clamp", "node selection", "", "none", false, "nodes fixed in x, y, z"},
    {"bodies.NAME", "supports", "list of supports", "", "none", false, "nodes held in some directions only: symmetry planes, rollers, 3-2-1 supports"},
    {"bodies.NAME", "masters", "node selection", "", "none", false, "extra boundary"},
    {"bodies.NAME", "modes", "integer in [0, 20000]", "", "`60`", false, "fixed-interface modes kept"},
    {"bodies.NAME", "mass_rule", "`exact` or `calculix`", "", "`exact`", false, "how the consistent mass of the body's elements is integrated"},
    {"bodies.NAME", "modal_damping_ratio", "number in [0, 1)", "–", "`0`", true, "ζ on every fixed-interface mode"},
    {"bodies.NAME", "reduced", "map", "", "–", false, "the body is given by matrices"},
    {"bodies.NAME", "cyclic", "map", "", "none", false, "the body is one sector of a cyclic structure (below)"},
    {"bodies.NAME.supports", "from_mesh", "boolean", "", "`false`", false, "the mesh's *BOUNDARY lines"},
    {"bodies.NAME.supports", "nodes", "node selection", "", "required", false, "the supported nodes"},
    {"bodies.NAME.supports", "directions", "list of `x`, `y`, `z`; with `normal`: of `t1`, `t2`, `n`", "", "required", false, "the directions held"},
    {"bodies.NAME.supports", "normal", "direction", "", "none (global axes)", false, "a local frame, built as the contact frames are: rows t1, t2, n with n = normal"},
    {"bodies.NAME.supports", "t1", "direction", "", "automatic", false, "hint for t1"},
    {"bodies.NAME.cyclic", "sectors", "integer in [2, 1000]", "", "required", false, "N: the structure is N copies of the sector"},
    {"bodies.NAME.cyclic", "axis", "map", "", "required", false, "the symmetry axis"},
    {"bodies.NAME.cyclic", "low", "node selection", "", "none", false, "the sector's low boundary (with high, or neither: a body that crosses no boundary)"},
    {"bodies.NAME.cyclic", "high", "node selection", "", "none", false, "the sector's high boundary: low rotated by 360°/N"},
    {"bodies.NAME.cyclic", "tolerance", "number > 0", "m", "`1.0e-6`", false, "how far a rotated low node may lie from its high node"},
    {"bodies.NAME.cyclic.axis", "point", "[x, y, z]", "m", "required", false, "a point of the axis"},
    {"bodies.NAME.cyclic.axis", "direction", "direction", "", "required", false, "the axis direction: sector j + 1 is sector j rotated by +360°/N about it (right hand)"},
    {"bodies.NAME.reduced", "stiffness", "path", "", "required", false, "reduced stiffness matrix"},
    {"bodies.NAME.reduced", "mass", "path", "", "required", false, "reduced mass matrix"},
    {"bodies.NAME.reduced", "mapping", "path", "", "HB: the stiffness path with extension `.mapping`; MM: required; Abaqus: not allowed", false, "ANSYS mapping file: equation → node, DOF label"},
    {"bodies.NAME.reduced", "format", "`harwell_boeing` | `matrix_market` | `abaqus_matrix`", "", "`matrix_market` if the stiffness file ends in `.mtx`, else `harwell_boeing`", false, "matrix format"},
    {"contacts[]", "name", "string", "", "required", false, "unique"},
    {"contacts[]", "law", "see above", "", "required", false, "friction | jenkins | gap | cubic | linear, or a law registered by the program"},
    {"contacts[]", "between", "map body → node selection", "", "one of `between`/`pairs`/`pairs_file`", false, "two bodies"},
    {"contacts[]", "tolerance", "number > 0", "m", "`1.0e-6`", false, "coincidence distance for between"},
    {"contacts[]", "coupling", "`auto` | `nodes` | `mortar` | `node_to_surface`", "", "`auto`", false, "between two bodies: coincident nodes, the two surfaces coupled by mortar weights, or each node of A projected onto B's faces (node_to_surface, CalculiX's NODE TO SURFACE); auto: nodes where the surfaces match node for node, else mortar"},
    {"contacts[]", "search_distance", "number ≥ 0", "m", "`0` (automatic: half the median edge of A's faces)", false, "coupling: mortar or node_to_surface: how far from A's faces B's faces are looked for"},
    {"contacts[]", "unpaired", "`error` | `skip`", "", "`error`", false, "coupling: mortar or node_to_surface: a point not wholly over B (node_to_surface: that projects onto no face of B) is an error, or left out with a warning"},
    {"contacts[]", "bodies", "[A, B]", "", "required with `pairs`/`pairs_file`", false, "the bodies the listed node ids belong to"},
    {"contacts[]", "pairs", "list of [id_A, id_B]", "", "", false, "pairs by external node ids"},
    {"contacts[]", "pairs_file", "path", "", "", false, "CSV, one pair per line: id_A,id_B"},
    {"contacts[]", "neighbour", "`next` | `previous`", "", "none", false, "cyclic sector: B's nodes are in the next (previous) sector"},
    {"contacts[]", "normal", "direction", "", "required for `friction` and 3D `linear`", false, "unit normal n, out of A into B"},
    {"contacts[]", "t1", "direction", "", "none (automatic)", false, "hint for the first tangent t1"},
    {"contacts[]", "direction", "direction", "", "required for 1D laws (and 1D `linear`)", false, "the axis the 1D element acts along"},
    {"contacts[]", "per_pair", "map of parameters", "", "one of `per_pair`/`total`", true, "the law's parameters for every pair"},
    {"contacts[]", "total", "map of parameters + `split`", "", "", true, "totals over all pairs: kt, kn, k, k1, k3, preload are split over the pairs"},
    {"contacts[]", "total.split", "`equal` | `area`", "", "`equal`", false, "split equally, or in proportion to each pair's tributary area"},
    {"contacts[]", "per_area", "map of parameters", "", "", true, "values per unit area, multiplied by each pair's area (N/m³; preload in Pa)"},
    {"contacts[]", "preload_file", "path", "", "none", false, "CSV, one line per pair: id_A,preload"},
    {"contacts[]", "gap", "number ≥ 0", "m", "`0`", true, "initial gap g0"},
    {"excitation[]", "body", "body name", "", "required", false, "the body the force acts on"},
    {"excitation[]", "node_set", "string or list", "", "one of `node_set`/`node`", false, "node set(s) of the body"},
    {"excitation[]", "node", "id or list of ids", "", "", false, "external node id(s)"},
    {"excitation[]", "harmonic", "integer ≥ 0", "", "`1`", false, "k: the force varies as e^{ikΩt}"},
    {"excitation[]", "engine_order", "integer ≥ 0", "", "none", false, "cyclic sector: the travelling wave's engine order EO (required there)"},
    {"excitation[]", "direction", "direction", "", "one of `direction`/`force`", false, "the force's line of action"},
    {"excitation[]", "amplitude", "number", "N", "required with `direction` (unless `complex`)", true, "the force amplitude A"},
    {"excitation[]", "phase_deg", "number", "degrees", "`0`", false, "φ: the force is A cos(kΩt + φ) along direction"},
    {"excitation[]", "complex", "[re, im]", "N", "", false, "the complex amplitude F = re + i·im instead of amplitude/phase_deg"},
    {"excitation[]", "force", "[fx, fy, fz]", "N", "", false, "the force vector"},
    {"static_loads[]", "body", "body name", "", "required", false, "a body given by a mesh"},
    {"static_loads[]", "node_set", "string or list", "", "one of `node_set`/`node`", false, "node set(s) of the body"},
    {"static_loads[]", "node", "id or list of ids", "", "", false, "external node id(s)"},
    {"static_loads[]", "force", "[fx, fy, fz]", "N", "one of `force`/`total_force`/`pressure`", true, "on **each** node"},
    {"static_loads[]", "total_force", "[fx, fy, fz]", "N", "", true, "the total, split over the nodes in proportion to their consistent nodal areas ∫ N_i dA …"},
    {"static_loads[]", "pressure", "number ≠ 0", "Pa", "", true, "on the faces whose nodes all lie in the selection: each node receives −p ∫ N_i n dA, n …"},
    {"rotation", "speed_rpm", "number ≥ 0", "rpm", "required", true, "the speed Ω of the rotation, revolutions per minute"},
    {"rotation", "axis", "map", "", "the cyclic body's axis; required without one", false, "the axis of rotation: point, direction"},
    {"rotation", "stress_stiffening", "bool", "", "`true`", false, "the geometric stiffness of the centrifugal prestress in every body's stiffness"},
    {"rotation", "spin_softening", "bool", "", "`true`", false, "−Ω² times the mass projected on the plane normal to the axis in every body's stiffness"},
    {"rotation", "campbell", "map", "", "none", false, "`stickslip modes` draws the Campbell diagram"},
    {"rotation.axis", "point", "[x, y, z]", "m", "required", false, "a point of the axis"},
    {"rotation.axis", "direction", "direction", "", "required", false, "the axis direction"},
    {"rotation.campbell", "speeds_rpm", "list of ≥ 2 increasing numbers ≥ 0", "rpm", "required", false, "the speeds of the diagram"},
    {"rotation.campbell", "engine_orders", "list of integers ≥ 1", "", "none", false, "the engine-order lines f = EO · speed drawn on it"},
    {"damping", "alpha", "number ≥ 0", "1/s", "`0`", true, "mass-proportional"},
    {"damping", "beta", "number ≥ 0", "s", "`0`", true, "stiffness-proportional"},
    {"analysis", "frequency", "map", "", "required (not with `nonlinear_mode`)", false, "the sweep"},
    {"analysis", "method", "`stepped` | `continuation` | `nonlinear_mode`", "", "`stepped`", false, "stepped sweep, continuation, or a nonlinear mode"},
    {"analysis", "mode", "integer ≥ 1", "", "required with `nonlinear_mode`", false, "the mode of the stuck assembly whose nonlinear mode is followed"},
    {"analysis", "amplitude", "map", "", "required with `nonlinear_mode`", false, "the modal amplitudes of the nonlinear mode"},
    {"analysis", "nonlinear_mode", "map", "", "none", false, "stepped or continuation: also the nonlinear mode, and the forced response predicted from it"},
    {"analysis", "harmonics", "integer H with 1 ≤ H ≤ 10000, or a strictly increasing list of integers in [1, 10000]", "", "`1`", false, "dynamic harmonics 1..H, or those listed"},
    {"analysis", "time_samples", "integer", "", "`64`", false, "N samples per period for AFT"},
    {"analysis", "aft", "`event` | `sampled`", "", "`event`", false, "how the contact forces' harmonics are computed from the displacement harmonics"},
    {"analysis", "static", "`uncoupled` | `coupled`", "", "`uncoupled`", false, "static contact state solved first and frozen, or harmonic 0 solved with the others"},
    {"analysis", "static_increments", "integer in [1, 10000]", "", "automatic", false, "load steps of the static contact problem"},
    {"analysis", "stability", "bool", "", "`false`", false, "Hill's method on every converged point: points.csv `stable`, `floquet_multiplier`, `floquet_unplaced`"},
    {"analysis", "tolerance", "number > 0", "", "`1.0e-8`", false, "Newton tolerance on the relative residual: ‖R‖₂ ≤ tolerance · s(Ω), with s(Ω)"},
    {"analysis", "max_iterations", "integer ≥ 1", "", "`30`", false, "Newton iterations per point"},
    {"analysis", "max_points", "integer in [2, 10⁶]", "", "`10000`", false, "continuation only: points at most"},
    {"analysis", "initial_guess", "`stuck` | `free`", "", "`stuck`", false, "first point's guess: linear response with the contacts stuck or free"},
    {"analysis", "predictor", "`secant` | `previous`", "", "`secant`", false, "stepped only: each point's Newton guess is the line through the last two solved …"},
    {"analysis.amplitude", "start", "number > 0", "√kg·m", "required", false, "smallest modal amplitude"},
    {"analysis.amplitude", "stop", "number > `start`", "√kg·m", "required", false, "largest modal amplitude"},
    {"analysis.amplitude", "points", "integer in [2, 10⁶]", "", "`50`", false, "amplitudes, evenly spaced in ln a"},
    {"analysis.nonlinear_mode", "mode", "integer ≥ 1", "", "required", false, "the mode of the stuck assembly"},
    {"analysis.nonlinear_mode", "amplitude", "map", "", "required", false, "its modal amplitudes: start, stop, points as analysis.amplitude"},
    {"analysis.frequency", "start_hz", "number > 0", "Hz", "required (range)", false, "first frequency"},
    {"analysis.frequency", "stop_hz", "number > `start_hz`", "Hz", "required (range)", false, "last frequency"},
    {"analysis.frequency", "around_mode", "integer ≥ 1", "", "–", false, "sweep f_m ± half_width_hz, f_m = the m-th natural frequency of the stuck assembly"},
    {"analysis.frequency", "half_width_hz", "number > 0", "Hz", "required with `around_mode`", false, "half the window around the mode"},
    {"analysis.frequency", "step_hz", "number > 0", "Hz", "required", false, "stepped: the step"},
    {"analysis.frequency", "min_step_hz", "number > 0", "Hz", "automatic", false, "continuation only"},
    {"analysis.frequency", "max_step_hz", "number > 0", "Hz", "automatic", false, "continuation only"},
    {"analysis.frequency", "sweep", "`up` | `down`", "", "`up`", false, "down: from the high end of the range"},
    {"study", "parameter", "dotted path", "", "required", false, "the key to vary"},
    {"study", "values", "list of numbers", "", "required (≥ 1)", false, "each must obey the key's rule"},
    {"recovery", "points", "`peak` | `all` | `none` | list of Hz", "", "`peak`", false, "which frequency points: the one with the largest response, every point, none, or the …"},
    {"recovery", "method", "`direct` | `modal` | `expansion`", "", "`direct`", false, "sparse complex factorisation of the full model"},
    {"recovery", "modes", "integer in [1, 10000]", "", "`100`", false, "modal only: full-model modes"},
    {"recovery", "fields", "list of `displacement`, `stress`", "", "both", false, "what is recovered and written"},
    {"recovery", "nodes", "list of node ids", "", "none", false, "nodes whose recovered response is also written as CSV"},
    {"recovery", "annulus", "bool", "", "`false`", false, "a cyclic sector: also the whole annulus, every sector's fields from sector 0's, as one VTU per point"},
    {"output", "directory", "path", "", "`results`", false, "output folder, relative to the case file"},
    {"output", "vtu", "bool", "", "`true`", false, "ParaView files of the recovered fields"},
    {"output", "plots", "bool", "", "`true`", false, "PNG and SVG plots"},
    {"output", "log_amplitude", "bool", "", "`false`", false, "amplitude plots (FRF) on a logarithmic axis"},
    {"output", "apdl_macro", "bool", "", "`false`", false, "the contact forces as an ANSYS APDL macro"},
    {"output", "calculix_deck", "bool", "", "`false`", false, "the contact forces in a CalculiX *STEADY STATE DYNAMICS deck"},
    {"output", "histories", "map contact name → pair index or list of 0-based pair indices", "", "none", false, "pairs whose hysteresis loop"},
    {"output", "frf", "list of {`body`, `node`, `direction`: x|y|z}", "", "none", false, "DOFs whose FRF amplitude is plotted"},
    {"output", "quiet", "bool", "", "`false`", false, "no progress output"},
    {"output.frf[]", "body", "body name", "", "required", false, "the body of the node"},
    {"output.frf[]", "node", "node id", "", "required", false, "external node id"},
    {"output.frf[]", "direction", "`x` | `y` | `z`", "", "required", false, "the displacement component plotted"},
  };
  // clang-format on
  return keys;
}

std::vector<std::string> case_keys_in(std::string_view section) {
  std::vector<std::string> out;
  for (const CaseKey& k : case_keys()) {
    if (k.section == section && k.key.find('.') == std::string_view::npos) out.emplace_back(k.key);
  }
  return out;
}

std::vector<std::string> study_parameter_paths() {
  std::vector<std::string> out;
  for (const CaseKey& k : case_keys()) {
    if (!k.study) continue;
    std::string section(k.section);
    // Lists are addressed by index, contacts by their name (the case file's `name`).
    if (section == "contacts[]") {
      section = "contacts.NAME";
    } else if (section.size() > 2 && section.substr(section.size() - 2) == "[]") {
      section = section.substr(0, section.size() - 2) + "[i]";
    }
    std::string path = section + "." + std::string(k.key);
    if (k.key == "per_pair" || k.key == "total" || k.key == "per_area") path += ".<parameter>";
    out.push_back(path);
  }
  return out;
}

}  // namespace stickslip
