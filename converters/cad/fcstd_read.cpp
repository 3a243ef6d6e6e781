// Reading a FreeCAD document (.FCStd: a zip archive holding Document.xml, GuiDocument.xml and each object's shape as
// an OCCT BREP file) into one shape made of the document's solids to mesh.
//
// Which objects: those with a Part shape (Part::PropertyPartShape "Shape") that contains at least one solid, and
//  1. among them the ones marked visible in GuiDocument.xml, when at least one is; otherwise (headless documents,
//     or everything hidden, as FEM documents often leave their parts)
//  2. the top-level ones: those that no other solid-bearing object links to (so a BooleanFragments or a PartDesign
//     Body is taken, and the boxes, pads and sketches it is made of are not).
// The stored shapes already carry their placement.
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS_Compound.hxx>
#include <zip.h>

#include <map>
#include <set>
#include <sstream>

#include "cad_private.h"
#include "qualmesh/error.h"

namespace qualmesh::cad {
namespace {

class ZipArchive {
 public:
  explicit ZipArchive(const std::string& path) : path_(path) {
    int error = 0;
    archive_ = zip_open(path.c_str(), ZIP_RDONLY, &error);
    if (!archive_) throw InputError(ErrorCode::Parse, "not a FreeCAD document (not a zip archive)", path);
  }
  ~ZipArchive() { zip_discard(archive_); }
  ZipArchive(const ZipArchive&) = delete;
  ZipArchive& operator=(const ZipArchive&) = delete;

  bool has(const std::string& name) const { return zip_name_locate(archive_, name.c_str(), 0) >= 0; }

  std::string read(const std::string& name) const {
    zip_stat_t stat;
    if (zip_stat(archive_, name.c_str(), 0, &stat) != 0)
      throw InputError(ErrorCode::Parse, "the FreeCAD document lacks " + name, path_);
    zip_file_t* file = zip_fopen(archive_, name.c_str(), 0);
    if (!file) throw InputError(ErrorCode::Parse, "cannot open " + name + " in the FreeCAD document", path_);
    std::string data(stat.size, '\0');
    zip_int64_t got = zip_fread(file, data.data(), stat.size);
    zip_fclose(file);
    if (got != static_cast<zip_int64_t>(stat.size))
      throw InputError(ErrorCode::Parse, "cannot read " + name + " in the FreeCAD document", path_);
    return data;
  }

 private:
  std::string path_;
  zip_t* archive_ = nullptr;
};

// Value of attribute `name` inside the tag text `tag`, "" when absent.
std::string attribute(const std::string& tag, const std::string& name) {
  std::string key = " " + name + "=\"";
  auto at = tag.find(key);
  if (at == std::string::npos) return {};
  at += key.size();
  return tag.substr(at, tag.find('"', at) - at);
}

// Bodies of the elements <tag name="..."> ... </tag> (not nested) inside `xml`, by name.
std::map<std::string, std::string> elements_by_name(const std::string& xml, const std::string& tag) {
  std::map<std::string, std::string> result;
  const std::string open = "<" + tag + " ", close = "</" + tag + ">";
  for (std::size_t at = xml.find(open); at != std::string::npos; at = xml.find(open, at + 1)) {
    std::size_t head_end = xml.find('>', at);
    std::size_t end = xml.find(close, head_end);
    if (head_end == std::string::npos || end == std::string::npos) break;
    std::string name = attribute(xml.substr(at, head_end - at), "name");
    if (!name.empty()) result[name] = xml.substr(head_end + 1, end - head_end - 1);
  }
  return result;
}

// The body of the <Property name="NAME" ...> element in an object's body, "" when absent.
std::string property(const std::string& body, const std::string& name) {
  auto at = body.find("<Property name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  auto end = body.find("</Property>", at);
  return body.substr(at, end == std::string::npos ? std::string::npos : end - at);
}

}  // namespace

TopoDS_Shape read_fcstd_file(const std::string& path, std::vector<std::string>& log) {
  silence_occt_messages();
  ZipArchive zip(path);
  const std::string document = zip.read("Document.xml");
  auto data_at = document.find("<ObjectData");
  if (data_at == std::string::npos) throw InputError(ErrorCode::Parse, "Document.xml has no ObjectData", path);
  const auto objects = elements_by_name(document.substr(data_at), "Object");

  // Solid-bearing objects and their shapes.
  std::map<std::string, TopoDS_Shape> solid_objects;
  for (const auto& [name, body] : objects) {
    std::string shape_property = property(body, "Shape");
    if (shape_property.find("Part::PropertyPartShape") == std::string::npos) continue;
    auto part_at = shape_property.find("<Part ");
    if (part_at == std::string::npos) continue;
    std::string file = attribute(shape_property.substr(part_at, shape_property.find('>', part_at) - part_at), "file");
    if (file.empty() || !zip.has(file)) continue;
    std::istringstream stream(zip.read(file));
    TopoDS_Shape shape;
    BRep_Builder builder;
    BRepTools::Read(shape, stream, builder);
    if (shape.IsNull()) continue;
    if (!TopExp_Explorer(shape, TopAbs_SOLID).More()) continue;
    solid_objects[name] = shape;
  }
  if (solid_objects.empty()) throw InputError(ErrorCode::Empty, "the FreeCAD document holds no solid", path);

  std::set<std::string> chosen;
  if (zip.has("GuiDocument.xml")) {
    const auto providers = elements_by_name(zip.read("GuiDocument.xml"), "ViewProvider");
    for (const auto& [name, shape] : solid_objects) {
      auto it = providers.find(name);
      if (it == providers.end()) continue;
      std::string visibility = property(it->second, "Visibility");
      if (visibility.find("<Bool value=\"true\"") != std::string::npos) chosen.insert(name);
    }
  }
  std::string rule = "visible";
  if (chosen.empty()) {
    rule = "top-level (none visible)";
    std::set<std::string> linked;
    for (const auto& [name, shape] : solid_objects) {
      const std::string& body = objects.at(name);
      for (std::size_t at = body.find("<Link"); at != std::string::npos; at = body.find("<Link", at + 1)) {
        std::string tag = body.substr(at, body.find('>', at) - at);
        for (const char* key : {"value", "obj"}) {
          std::string target = attribute(tag, key);
          if (!target.empty() && target != name) linked.insert(target);
        }
      }
    }
    for (const auto& [name, shape] : solid_objects)
      if (!linked.count(name)) chosen.insert(name);
  }
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  std::string names;
  for (const auto& name : chosen) {
    builder.Add(compound, solid_objects.at(name));
    names += (names.empty() ? "" : ", ") + name;
  }
  log.push_back("FreeCAD document: took the " + rule + " solid object(s) " + names);
  return compound;
}

}  // namespace qualmesh::cad
