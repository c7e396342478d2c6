// The text <-> enum table of a scenario choice (actuation, fluid.model,
// ...): one line per value, in the order `ipmc-swim keys` lists them. The
// key table takes a choice key's allowed values from it and its reader
// parses the text into the enum once; the run reads only the enum.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ipmc {

template <typename Enum>
struct ChoiceName {
  const char* text;
  Enum value;
};

// The value of `text` in `table`; the key's reader has checked `text`
// against the table's own texts.
template <typename Enum, std::size_t N>
Enum ChoiceValue(const ChoiceName<Enum> (&table)[N], std::string_view text) {
  for (const ChoiceName<Enum>& entry : table) {
    if (text == entry.text) return entry.value;
  }
  throw std::logic_error("'" + std::string(text) + "' is not a choice of its table");
}

// The text of `value` in `table`.
template <typename Enum, std::size_t N>
const char* ChoiceText(const ChoiceName<Enum> (&table)[N], Enum value) {
  for (const ChoiceName<Enum>& entry : table) {
    if (value == entry.value) return entry.text;
  }
  throw std::logic_error("a choice value missing from its table");
}

// The texts as KeySpec::choices holds them: "rft|stokeslets".
template <typename Enum, std::size_t N>
std::string ChoiceTexts(const ChoiceName<Enum> (&table)[N]) {
  std::string texts;
  for (const ChoiceName<Enum>& entry : table) {
    texts += (texts.empty() ? "" : "|") + std::string(entry.text);
  }
  return texts;
}

}  // namespace ipmc
