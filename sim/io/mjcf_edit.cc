#include "sim/io/mjcf_edit.h"

#include <cctype>
#include <optional>
#include <stdexcept>
#include <string>

#include "sim/base/numbers.h"

namespace ipmc {
namespace {

// A start tag (or empty-element tag) in the text: [begin, end) from '<'
// to past '>', and its element name.
struct Tag {
  size_t begin = 0, end = 0;
  std::string name;
};

// The next start tag at or after `from`, skipping comments, declarations,
// processing instructions and end tags; nullopt at the end of the text.
std::optional<Tag> NextStartTag(const std::string& xml, size_t from) {
  size_t at = xml.find('<', from);
  while (at != std::string::npos) {
    const auto skip_to = [&](const char* close) {
      const size_t stop = xml.find(close, at);
      return stop == std::string::npos ? std::string::npos : stop + std::string(close).size();
    };
    size_t next = std::string::npos;
    if (xml.compare(at, 4, "<!--") == 0) {
      next = skip_to("-->");
    } else if (xml.compare(at, 9, "<![CDATA[") == 0) {
      next = skip_to("]]>");
    } else if (xml.compare(at, 2, "<?") == 0) {
      next = skip_to("?>");
    } else if (xml.compare(at, 2, "<!") == 0 || xml.compare(at, 2, "</") == 0) {
      next = skip_to(">");
    } else {
      Tag tag;
      tag.begin = at;
      size_t i = at + 1;
      while (i < xml.size() && !std::isspace(static_cast<unsigned char>(xml[i])) &&
             xml[i] != '/' && xml[i] != '>') {
        tag.name += xml[i++];
      }
      char quote = 0;
      for (; i < xml.size(); ++i) {
        if (quote) {
          if (xml[i] == quote) quote = 0;
        } else if (xml[i] == '"' || xml[i] == '\'') {
          quote = xml[i];
        } else if (xml[i] == '>') {
          break;
        }
      }
      if (i >= xml.size()) return std::nullopt;
      tag.end = i + 1;
      return tag;
    }
    if (next == std::string::npos) return std::nullopt;
    at = xml.find('<', next);
  }
  return std::nullopt;
}

// The value range [first, second) of `attribute` in the tag, or nullopt.
std::optional<std::pair<size_t, size_t>> AttributeValue(const std::string& xml, const Tag& tag,
                                                        const std::string& attribute) {
  size_t i = tag.begin + 1 + tag.name.size();
  while (i < tag.end) {
    while (i < tag.end && std::isspace(static_cast<unsigned char>(xml[i]))) ++i;
    const size_t name_begin = i;
    while (i < tag.end && xml[i] != '=' && xml[i] != '>' && xml[i] != '/' &&
           !std::isspace(static_cast<unsigned char>(xml[i]))) {
      ++i;
    }
    const std::string name = xml.substr(name_begin, i - name_begin);
    while (i < tag.end && std::isspace(static_cast<unsigned char>(xml[i]))) ++i;
    if (i >= tag.end || xml[i] != '=') {
      if (name.empty()) ++i;
      continue;
    }
    ++i;
    while (i < tag.end && std::isspace(static_cast<unsigned char>(xml[i]))) ++i;
    if (i >= tag.end || (xml[i] != '"' && xml[i] != '\'')) return std::nullopt;
    const char quote = xml[i];
    const size_t value_begin = i + 1;
    const size_t value_end = xml.find(quote, value_begin);
    if (value_end == std::string::npos || value_end >= tag.end) return std::nullopt;
    if (name == attribute) return std::make_pair(value_begin, value_end);
    i = value_end + 1;
  }
  return std::nullopt;
}

// The tag with `attribute` set to `value` (added before its '>' or '/>').
std::string WithAttribute(const std::string& xml, const Tag& tag, const std::string& attribute,
                          const std::string& value) {
  std::string text = xml.substr(tag.begin, tag.end - tag.begin);
  if (const auto range = AttributeValue(xml, tag, attribute)) {
    return text.substr(0, range->first - tag.begin) + value +
           text.substr(range->second - tag.begin);
  }
  const size_t close = text.size() - (text.size() >= 2 && text[text.size() - 2] == '/' ? 2 : 1);
  return text.substr(0, close) + " " + attribute + "=\"" + value + "\"" + text.substr(close);
}

// The tag without `attribute`.
std::string WithoutAttribute(const std::string& xml, const Tag& tag, const std::string& attribute) {
  std::string text = xml.substr(tag.begin, tag.end - tag.begin);
  const auto range = AttributeValue(xml, tag, attribute);
  if (!range) return text;
  size_t begin = range->first - tag.begin;
  while (begin > 0 && text[begin - 1] != ' ' && text[begin - 1] != '\t' &&
         text[begin - 1] != '\n') {
    --begin;
  }
  while (begin > 0 && std::isspace(static_cast<unsigned char>(text[begin - 1]))) --begin;
  return text.substr(0, begin) + text.substr(range->second - tag.begin + 1);
}

std::optional<Tag> FindTag(const std::string& xml, const std::string& name) {
  for (std::optional<Tag> tag = NextStartTag(xml, 0); tag; tag = NextStartTag(xml, tag->end)) {
    if (tag->name == name) return tag;
  }
  return std::nullopt;
}

// The <numeric> or <text> element named `name` (whichever kind).
std::optional<Tag> FindCustomField(const std::string& xml, const std::string& name) {
  for (std::optional<Tag> tag = NextStartTag(xml, 0); tag; tag = NextStartTag(xml, tag->end)) {
    if (tag->name != "numeric" && tag->name != "text") continue;
    const auto range = AttributeValue(xml, *tag, "name");
    if (range && xml.compare(range->first, range->second - range->first, name) == 0 &&
        range->second - range->first == name.size()) {
      return tag;
    }
  }
  return std::nullopt;
}

std::string Replaced(const std::string& xml, const Tag& tag, const std::string& text) {
  return xml.substr(0, tag.begin) + text + xml.substr(tag.end);
}

}  // namespace

std::string SetMjcfOption(const std::string& xml, const std::string& attribute,
                          const std::string& value) {
  if (const std::optional<Tag> option = FindTag(xml, "option")) {
    return Replaced(xml, *option, WithAttribute(xml, *option, attribute, value));
  }
  const std::optional<Tag> root = FindTag(xml, "mujoco");
  if (!root) throw std::runtime_error("the model's MJCF has no <mujoco> element");
  return xml.substr(0, root->end) + "\n  <option " + attribute + "=\"" + value + "\"/>" +
         xml.substr(root->end);
}

std::string ScaleMjcfJointDamping(const std::string& xml, double scale) {
  std::string out;
  size_t copied = 0;
  for (std::optional<Tag> tag = NextStartTag(xml, 0); tag; tag = NextStartTag(xml, tag->end)) {
    if (tag->name != "joint") continue;
    const auto range = AttributeValue(xml, *tag, "damping");
    if (!range) continue;
    const std::optional<double> damping =
        ParseDouble(std::string_view(xml).substr(range->first, range->second - range->first));
    if (!damping) continue;  // MuJoCo names it when it loads the text
    out += xml.substr(copied, range->first - copied) + FormatShortest(*damping * scale);
    copied = range->second;
  }
  return out + xml.substr(copied);
}

std::string SetMjcfCustomField(const std::string& xml, const std::string& element,
                               const std::string& name, const std::string& data) {
  const std::string field =
      "<" + element + " name=\"" + name + "\" data=\"" + data + "\"/>";
  if (const std::optional<Tag> tag = FindCustomField(xml, name)) {
    if (tag->name == element) {
      const std::string edited = WithAttribute(xml, *tag, "data", data);
      Tag rewritten = *tag;
      std::string with_data = xml.substr(0, tag->begin) + edited + xml.substr(tag->end);
      rewritten.end = tag->begin + edited.size();
      return element == "numeric"
                 ? Replaced(with_data, rewritten, WithoutAttribute(with_data, rewritten, "size"))
                 : with_data;
    }
    return Replaced(xml, *tag, field);
  }
  const size_t end = xml.rfind("</mujoco>");
  if (end == std::string::npos) throw std::runtime_error("the model's MJCF has no </mujoco>");
  return xml.substr(0, end) + "  <custom>\n    " + field + "\n  </custom>\n" + xml.substr(end);
}

std::string RemoveMjcfCustomField(const std::string& xml, const std::string& name) {
  const std::optional<Tag> tag = FindCustomField(xml, name);
  return tag ? Replaced(xml, *tag, "") : xml;
}

}  // namespace ipmc
