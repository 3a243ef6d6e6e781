// Reading STEP, IGES and OCCT BREP files into one OpenCASCADE shape (the first stage of the CAD front end).
// Lengths come out in millimetres (OpenCASCADE's default unit for STEP and IGES); BREP files carry no unit.
// OpenCASCADE failures become InputError, so that a bad file never reaches the mesher as a crash.
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <IGESControl_Reader.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopoDS_Shape.hxx>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <mutex>

#include "cad_private.h"
#include "qualmesh/error.h"

namespace qualmesh::cad {

void silence_occt_messages() {
  static std::once_flag once;
  std::call_once(once, [] {
    const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
    messenger->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  });
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

namespace {

std::string describe(IFSelect_ReturnStatus status) {
  switch (status) {
    case IFSelect_RetVoid: return "nothing to read";
    case IFSelect_RetError: return "the file could not be read";
    case IFSelect_RetFail: return "the file is not valid";
    case IFSelect_RetStop: return "reading was stopped";
    default: return "unknown status";
  }
}

}  // namespace

TopoDS_Shape read_occt_file(const std::string& path, const std::string& format) {
  silence_occt_messages();
  if (!std::filesystem::exists(path)) throw InputError(ErrorCode::Io, "no such file", path);
  TopoDS_Shape shape;
  try {
    if (format == "STEP") {
      STEPControl_Reader reader;
      IFSelect_ReturnStatus status = reader.ReadFile(path.c_str());
      if (status != IFSelect_RetDone)
        throw InputError(ErrorCode::Parse, "not a readable STEP file: " + describe(status), path);
      if (reader.TransferRoots() == 0)
        throw InputError(ErrorCode::Empty, "the STEP file holds no shape that OpenCASCADE can transfer", path);
      shape = reader.OneShape();
    } else if (format == "IGES") {
      IGESControl_Reader reader;
      IFSelect_ReturnStatus status = reader.ReadFile(path.c_str());
      if (status != IFSelect_RetDone)
        throw InputError(ErrorCode::Parse, "not a readable IGES file: " + describe(status), path);
      if (reader.TransferRoots() == 0)
        throw InputError(ErrorCode::Empty, "the IGES file holds no shape that OpenCASCADE can transfer", path);
      shape = reader.OneShape();
    } else if (format == "BREP") {
      BRep_Builder builder;
      if (!BRepTools::Read(shape, path.c_str(), builder))
        throw InputError(ErrorCode::Parse, "not a readable OpenCASCADE BREP file", path);
    } else {
      throw InputError(ErrorCode::Unsupported, "unknown CAD format " + format, path);
    }
  } catch (const Standard_Failure& failure) {
    throw InputError(ErrorCode::Parse,
                     std::string("OpenCASCADE failed to read the file: ") + failure.GetMessageString(), path);
  }
  if (shape.IsNull()) throw InputError(ErrorCode::Empty, "the file holds no shape", path);
  return shape;
}

}  // namespace qualmesh::cad
