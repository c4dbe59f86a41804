// libFuzzer target: a URDF as `kincal model --urdf U.urdf --tip tip` reads it and `kincal
// export --format urdf` writes it back (cli/urdf_xml.hpp, cli/urdf_io.hpp).
//  - What the scanner accepts, TinyXML (urdfdom's parser) reads without error as the same
//    elements, nesting and attribute values: the scanner's edits land where urdfdom reads.
//  - Any input is imported or refused with UrdfError or std::invalid_argument (the arm's own
//    checks) carrying one line of at most 1,000 characters: no crash, no other exception.
//  - An import exports into the user's text, whose reading by urdfdom export_urdf_arm checks
//    against what it meant to write (a refusal in its words, e.g. a link already named tcp,
//    is fine; "does not read back" is a fault).

#include <tinyxml.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "kincal/models/urdf_io.hpp"
#include "kincal/models/point_tracker.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_urdf_file: %s: %s\n", what, detail.substr(0, 2000).c_str());
  std::abort();
}

void check_message(const std::string& what) {
  if (what.find('\n') != std::string::npos) fail("message is not one line", what);
  if (what.size() > 1000) fail("message too long", what);
}

// Each element as "depth name attribute=value ...", in document order.
std::vector<std::string> tinyxml_elements(const std::string& text) {
  TiXmlDocument doc;
  doc.Parse(("\xEF\xBB\xBF" + text).c_str());  // as urdfdom is given it: UTF-8
  if (doc.Error())
    fail("TinyXML refuses what the scanner accepts", doc.ErrorDesc() + ("\n" + text));
  std::vector<std::string> out;
  std::vector<std::pair<const TiXmlNode*, int>> stack;
  for (const TiXmlNode* n = doc.LastChild(); n; n = n->PreviousSibling()) stack.push_back({n, 1});
  while (!stack.empty()) {
    const auto [node, depth] = stack.back();
    stack.pop_back();
    const TiXmlElement* e = node->ToElement();
    if (!e) continue;
    std::string seen = std::to_string(depth) + " " + e->ValueStr();
    for (const TiXmlAttribute* a = e->FirstAttribute(); a; a = a->Next())
      seen += std::string(" ") + a->Name() + "=" + a->Value();
    out.push_back(seen);
    for (const TiXmlNode* c = node->LastChild(); c; c = c->PreviousSibling())
      stack.push_back({c, depth + 1});
  }
  return out;
}

std::vector<std::string> scanned_elements(const kincal::XmlText& xml) {
  std::vector<std::string> out;
  for (const kincal::XmlElement& e : xml.elements) {
    int depth = 1;
    for (int p = e.parent; p >= 0; p = xml.elements[static_cast<std::size_t>(p)].parent) ++depth;
    std::string seen = std::to_string(depth) + " " + e.name;
    for (const kincal::XmlAttribute& a : e.attributes) seen += " " + a.name + "=" + a.value;
    out.push_back(seen);
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const kincal::XmlText xml = kincal::scan_urdf_xml(text);
    if (scanned_elements(xml) != tinyxml_elements(text)) fail("TinyXML reads other elements", text);
  } catch (const kincal::UrdfError& e) {
    check_message(e.what());
    return 0;
  }
  std::shared_ptr<kincal::MeasurementModel> model;
  try {
    kincal::UrdfArmGeometry g = kincal::import_urdf(text, "U.urdf", "", "tip");
    auto arm = std::make_shared<kincal::UrdfArm>(std::move(g));
    auto tracker = std::make_shared<kincal::PointTracker>("tracker", kincal::Vector6d::Zero(),
                                                          kincal::Vector3d(1, 2, 3));
    model = std::make_shared<kincal::MeasurementModel>(
        arm, std::vector<std::shared_ptr<const kincal::Sensor>>{tracker});
  } catch (const kincal::UrdfError& e) {
    check_message(e.what());
    return 0;
  } catch (const std::invalid_argument& e) {
    check_message(e.what());
    return 0;
  }
  // Corrections on every parameter, so that every origin on the chain is written.
  kincal::VectorXd values = model->parameters().nominal_values();
  for (int i = 0; i < values.size(); ++i) values[i] += 1e-3 * (i % 7 + 1);
  try {
    kincal::export_urdf_arm(*model, values, " fuzz -- header ");
  } catch (const kincal::UrdfError& e) {
    const std::string what = e.what();
    check_message(what);
    if (what.find("does not read back") != std::string::npos) fail("export", what + "\n" + text);
  }
  return 0;
}
