// Edits of MJCF text that leave everything else byte for byte: the
// scenario's overrides written into a model, so that the file is the
// model a run steps (numbers in their shortest exact form, FormatShortest;
// MuJoCo's own writer, mj_saveLastXML, rounds them to 6 digits).
// Comments, processing instructions and CDATA are skipped; elements in
// included files are not seen.
#pragma once

#include <string>

namespace ipmc {

// Sets `attribute` of the <option> element (adding one after the <mujoco>
// element's start tag if there is none). Throws std::runtime_error if the
// text has no <mujoco> element.
std::string SetMjcfOption(const std::string& xml, const std::string& attribute,
                          const std::string& value);

// Multiplies the damping attribute of every <joint> element (also those of
// <default> classes) by `scale`: every joint's damping scaled, as
// MuJoCo's default damping is 0.
std::string ScaleMjcfJointDamping(const std::string& xml, double scale);

// Sets the data of the <custom> field `name`, a <numeric> or <text>
// element (`element`), replacing the one the text has or adding one in a
// <custom> section of its own before </mujoco>. A numeric field's size
// attribute is dropped (MuJoCo takes it from the data).
std::string SetMjcfCustomField(const std::string& xml, const std::string& element,
                               const std::string& name, const std::string& data);

// Removes the <custom> field `name` if the text has it.
std::string RemoveMjcfCustomField(const std::string& xml, const std::string& name);

}  // namespace ipmc
