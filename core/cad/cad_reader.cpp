// The one reader of CAD files: OCCT reads and transfers the file, this file
// copies each face's B-spline (converted by OCCT when the face is analytic)
// and each free curve into the kernel's NURBS types. Every OCCT include of
// the reader is here, so only this file pays their compile time.
#include <BRepAdaptor_Curve2d.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_IGESEntity.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>

#include "core/cad/cad.h"
#include "core/cad/occt_setup.h"
#include "core/common/error.h"
#include "core/geometry/bspline_basis.h"

namespace bliskrun {

namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

// OCCT reports through a global messenger that prints to stdout; bliskrun
// reports through its own errors, so the printers go, once per process.
void detail::quiet_occt() {
  static std::once_flag once;
  std::call_once(once, [] {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    m->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
    // The controllers register the data-exchange parameters; only then can
    // they be set. Lengths of transferred shapes in mm, whatever the file's
    // unit (OCCT's default too, stated here as the reader's contract).
    IGESControl_Controller::Init();
    STEPControl_Controller::Init();
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
  });
}

namespace {

// Line of the file where an entity starts, for errors: IGES D-record n sits
// after the S and G sections; STEP entity #n on the line holding "#n=".
long entity_line(const std::string& path, bool iges, long number) {
  std::ifstream f(path);
  std::string line;
  long k = 0, before_d = 0;
  const std::string tag = "#" + std::to_string(number);
  while (std::getline(f, line)) {
    ++k;
    if (iges) {
      if (line.size() >= 73 && line[72] == 'D') return before_d + number;
      ++before_d;
    } else {
      const auto at = line.find(tag);
      if (at != std::string::npos) {
        auto rest = line.find_first_not_of(" \t", at + tag.size());
        if (rest != std::string::npos && line[rest] == '=') return k;
      }
    }
  }
  return 0;
}

class Reader {
 public:
  Reader(const std::string& path, bool iges) : path_(path), iges_(iges) {}

  [[noreturn]] void fail(long line, const std::string& what) const { throw DataError(path_, line, what); }

  // "IGES D17 (type 128)" / "STEP #123 (ADVANCED_FACE)" and its file line.
  std::string label(const Handle(Standard_Transient)& ent, long* line = nullptr) const {
    if (ent.IsNull() || model_.IsNull()) return "";
    const Standard_Integer n = model_->Number(ent);
    if (n <= 0) return "";
    if (iges_) {
      const long d = 2L * n - 1;  // entity n's first directory record
      if (line) *line = entity_line(path_, true, d);
      const Handle(IGESData_IGESEntity) ie = Handle(IGESData_IGESEntity)::DownCast(ent);
      return "IGES D" + std::to_string(d) +
             (ie.IsNull() ? "" : " (type " + std::to_string(ie->TypeNumber()) + ")");
    }
    const Handle(TCollection_HAsciiString) id = model_->StringLabel(ent);
    std::string s = id.IsNull() ? "#" + std::to_string(n) : id->ToCString();
    if (line && s.size() > 1 && s[0] == '#') *line = entity_line(path_, false, std::atol(s.c_str() + 1));
    return "STEP " + s + " (" + model_->TypeName(ent, Standard_False) + ")";
  }

  std::string name_of(const Handle(Standard_Transient)& ent) const {
    if (ent.IsNull()) return "";
    if (const auto ie = Handle(IGESData_IGESEntity)::DownCast(ent); !ie.IsNull()) {
      if (ie->HasName()) return trim(ie->NameValue()->ToCString());
      if (ie->HasShortLabel()) return trim(ie->ShortLabel()->ToCString());
    }
    if (const auto ri = Handle(StepRepr_RepresentationItem)::DownCast(ent); !ri.IsNull())
      if (!ri->Name().IsNull()) return trim(ri->Name()->ToCString());
    return "";
  }

  Handle(Standard_Transient) entity_of(const TopoDS_Shape& s) const {
    if (tr_.IsNull()) return Handle(Standard_Transient)();
    // 1: the shape as any transfer's result; -1: also under another location.
    Handle(Standard_Transient) e = tr_->EntityFromShapeResult(s, 1);
    if (e.IsNull()) e = tr_->EntityFromShapeResult(s, -1);
    return e;
  }

  // A face's or curve's entity label (and its line in the file), its name
  // (`fallback` when the file gives none); returns what messages call it.
  std::string identify(const TopoDS_Shape& s, const std::string& fallback, std::string* entity, std::string* name,
                       long* line) const {
    const Handle(Standard_Transient) ent = entity_of(s);
    *entity = label(ent, line);
    *name = name_of(ent);
    if (name->empty()) *name = fallback;
    return entity->empty() ? *name : *entity;
  }

  CadModel read() {
    CadModel out;
    out.path = path_;
    out.format = iges_ ? "IGES" : "STEP";
    // A folder opens as a stream on Linux; OCCT must get a file.
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec) || !std::ifstream(path_))
      fail(0, "cannot open the file for reading");
    IGESControl_Reader ir;
    STEPControl_Reader sr;
    XSControl_Reader& r = iges_ ? static_cast<XSControl_Reader&>(ir) : sr;
    const IFSelect_ReturnStatus st = r.ReadFile(path_.c_str());
    if (st != IFSelect_RetDone)
      fail(0, std::string("not a readable ") + out.format +
                  " file (truncated or corrupt; OpenCASCADE status " + std::to_string(int(st)) + ")");
    model_ = r.Model();
    tr_ = r.WS()->TransferReader();
    if (iges_) {
      const IGESData_GlobalSection& g = ir.IGESModel()->GlobalSection();
      out.file_units = g.UnitName().IsNull() ? "" : g.UnitName()->ToCString();
    } else {
      TColStd_SequenceOfAsciiString len, ang, solid;
      sr.FileUnits(len, ang, solid);
      for (int i = 1; i <= len.Length(); ++i) {
        const std::string u = len.Value(i).ToCString();
        if (!out.file_units.empty() && out.file_units != u)
          fail(0, "inconsistent length units: the file uses both " + out.file_units + " and " + u);
        out.file_units = u;
      }
    }
    const int roots = r.NbRootsForTransfer();
    if (roots == 0) fail(0, "no geometry to read: the file holds no surface and no curve");
    for (int i = 1; i <= roots; ++i) {
      const Handle(Standard_Transient) ent = r.RootForTransfer(i);
      bool ok = false;
      try {
        ok = r.TransferOneRoot(i);
      } catch (const Standard_Failure& e) {
        long line = 0;
        const std::string where = label(ent, &line);
        fail(line, where + ": OpenCASCADE failed on it: " + e.GetMessageString());
      }
      if (!ok) {
        long line = 0;
        const std::string where = label(ent, &line);
        fail(line, where + ": unsupported or invalid entity (OpenCASCADE could not convert it)");
      }
    }
    TopTools_IndexedMapOfShape faces, edges;
    for (int i = 1; i <= r.NbShapes(); ++i) {
      const TopoDS_Shape s = r.Shape(i);
      TopExp::MapShapes(s, TopAbs_FACE, faces);
      // Edges outside every face: the file's free curves.
      for (TopExp_Explorer x(s, TopAbs_EDGE, TopAbs_FACE); x.More(); x.Next()) edges.Add(x.Current());
    }
    for (int i = 1; i <= faces.Extent(); ++i) out.faces.push_back(face(TopoDS::Face(faces(i)), i));
    for (int i = 1; i <= edges.Extent(); ++i)
      if (auto c = curve(TopoDS::Edge(edges(i)), static_cast<int>(out.curves.size()) + 1))
        out.curves.push_back(std::move(*c));
    if (out.faces.empty() && out.curves.empty())
      fail(0, "no geometry to read: the file holds no surface and no curve OpenCASCADE could convert");
    return out;
  }

 private:
  static std::string trim(std::string s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    size_t a = 0;
    while (a < s.size() && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    return s.substr(a);
  }

  static std::vector<double> flat(const TColStd_Array1OfReal& a) {
    std::vector<double> v;
    for (int i = a.Lower(); i <= a.Upper(); ++i) v.push_back(a(i));
    return v;
  }

  CadFace face(const TopoDS_Face& f, int k) {
    CadFace out;
    long line = 0;
    const std::string where = identify(f, "face_" + std::to_string(k), &out.entity, &out.name, &line);
    TopoDS_Face work = f;
    Handle(Geom_BSplineSurface) bs = bspline_of(BRep_Tool::Surface(work));
    if (bs.IsNull()) {
      try {
        // Analytic and swept faces: OCCT's exact conversion, bounded by the
        // face (a plane or a cylinder is infinite until then).
        BRepBuilderAPI_NurbsConvert nc(f, Standard_True);
        work = TopoDS::Face(nc.Shape());
        bs = bspline_of(BRep_Tool::Surface(work));
      } catch (const Standard_Failure& e) {
        fail(line, where + ": its surface could not be converted to NURBS: " + e.GetMessageString());
      }
    }
    if (bs.IsNull()) fail(line, where + ": its surface could not be converted to NURBS");
    bs = Handle(Geom_BSplineSurface)::DownCast(bs->Copy());
    if (bs->IsUPeriodic()) bs->SetUNotPeriodic();
    if (bs->IsVPeriodic()) bs->SetVNotPeriodic();
    if (bs->UDegree() > detail::kMaxDegree || bs->VDegree() > detail::kMaxDegree)
      fail(line, where + ": surface of degree " + std::to_string(bs->UDegree()) + " x " +
                     std::to_string(bs->VDegree()) + " (bliskrun evaluates degrees up to " +
                     std::to_string(detail::kMaxDegree) + ")");
    const int rows = bs->NbUPoles(), cols = bs->NbVPoles();
    std::vector<Vec3> ctrl;
    std::vector<double> w;
    ctrl.reserve(static_cast<size_t>(rows) * cols);
    // OCCT 7.6 leaves the weights of a non-rational surface zero after
    // SetUNotPeriodic: weights are read only from a rational one.
    const bool rational = bs->IsURational() || bs->IsVRational();
    for (int i = 1; i <= rows; ++i)
      for (int j = 1; j <= cols; ++j) {
        const gp_Pnt p = bs->Pole(i, j);
        ctrl.emplace_back(p.X(), p.Y(), p.Z());
        w.push_back(rational ? bs->Weight(i, j) : 1.0);
      }
    check_not_degenerate(ctrl, rows, cols, line, where);
    TColStd_Array1OfReal ku(1, rows + bs->UDegree() + 1), kv(1, cols + bs->VDegree() + 1);
    bs->UKnotSequence(ku);
    bs->VKnotSequence(kv);
    try {
      out.surface = std::make_shared<NurbsSurface>(bs->UDegree(), bs->VDegree(), flat(ku), flat(kv),
                                                   rows, cols, std::move(ctrl), std::move(w));
    } catch (const ParameterError& e) {
      fail(line, where + ": " + e.what());
    }
    boundary(work, *bs, out);
    return out;
  }

  static Handle(Geom_BSplineSurface) bspline_of(const Handle(Geom_Surface)& s) {
    if (const auto t = Handle(Geom_RectangularTrimmedSurface)::DownCast(s); !t.IsNull())
      return Handle(Geom_BSplineSurface)::DownCast(t->BasisSurface());
    return Handle(Geom_BSplineSurface)::DownCast(s);
  }

  // A surface whose whole boundary row or column of poles is one point has a
  // collapsed edge: its normal is undefined along it, and planners that walk
  // rows from that edge cannot start. Refused rather than planned wrongly.
  void check_not_degenerate(const std::vector<Vec3>& c, int rows, int cols, long line,
                            const std::string& where) const {
    Vec3 lo = c.front(), hi = c.front();
    for (const Vec3& p : c) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double tol = 1e-9 * std::max(1.0, (hi - lo).norm());
    auto collapsed = [&](int i0, int j0, int di, int dj, int n) {
      for (int k = 1; k < n; ++k)
        if ((c[static_cast<size_t>(i0 + k * di) * cols + j0 + k * dj] - c[static_cast<size_t>(i0) * cols + j0]).norm() > tol)
          return false;
      return true;
    };
    if ((hi - lo).norm() <= tol) fail(line, where + ": degenerate surface (all its control points coincide)");
    const char* edge = collapsed(0, 0, 0, 1, cols)              ? "u = 0"
                       : collapsed(rows - 1, 0, 0, 1, cols)     ? "u = 1"
                       : collapsed(0, 0, 1, 0, rows)            ? "v = 0"
                       : collapsed(0, cols - 1, 1, 0, rows)     ? "v = 1"
                                                                : nullptr;
    if (edge) fail(line, where + ": degenerate surface (its " + edge + " edge collapses to a point)");
  }

  // The outer wire sampled along each edge, in the surface's [0, 1]^2.
  void boundary(const TopoDS_Face& f, const Geom_BSplineSurface& bs, CadFace& out) const {
    const TopoDS_Wire wire = BRepTools::OuterWire(f);
    if (wire.IsNull()) return;
    double u0, u1, v0, v1;
    bs.Bounds(u0, u1, v0, v1);
    constexpr int kPerEdge = 24;
    for (BRepTools_WireExplorer x(wire, f); x.More(); x.Next()) {
      const TopoDS_Edge& e = x.Current();
      BRepAdaptor_Curve2d c(e, f);
      const double a = c.FirstParameter(), b = c.LastParameter();
      const bool rev = e.Orientation() == TopAbs_REVERSED;
      for (int k = 0; k < kPerEdge; ++k) {
        const double s = rev ? 1.0 - double(k) / kPerEdge : double(k) / kPerEdge;
        const gp_Pnt2d p = c.Value(a + (b - a) * s);
        out.boundary_uv.emplace_back((p.X() - u0) / (u1 - u0), (p.Y() - v0) / (v1 - v0));
      }
    }
    if (out.boundary_uv.empty()) return;
    out.boundary_uv.push_back(out.boundary_uv.front());
    out.u_min = out.v_min = 1;
    out.u_max = out.v_max = 0;
    for (const Vec2& p : out.boundary_uv) {
      out.boundary_mm.push_back(out.surface->point(p.x(), p.y()));
      out.u_min = std::min(out.u_min, std::clamp(p.x(), 0.0, 1.0));
      out.u_max = std::max(out.u_max, std::clamp(p.x(), 0.0, 1.0));
      out.v_min = std::min(out.v_min, std::clamp(p.y(), 0.0, 1.0));
      out.v_max = std::max(out.v_max, std::clamp(p.y(), 0.0, 1.0));
    }
  }

  std::optional<CadCurve> curve(const TopoDS_Edge& e, int k) const {
    if (BRep_Tool::Degenerated(e)) return std::nullopt;
    Standard_Real a = 0, b = 0;
    const Handle(Geom_Curve) gc = BRep_Tool::Curve(e, a, b);
    if (gc.IsNull()) return std::nullopt;
    CadCurve out;
    long line = 0;
    const std::string where = identify(e, "curve_" + std::to_string(k), &out.entity, &out.name, &line);
    Handle(Geom_BSplineCurve) bc = Handle(Geom_BSplineCurve)::DownCast(gc);
    try {
      const double eps = 1e-12 * (1 + std::abs(a) + std::abs(b));
      if (bc.IsNull() || a > bc->FirstParameter() + eps || b < bc->LastParameter() - eps)
        bc = GeomConvert::CurveToBSplineCurve(new Geom_TrimmedCurve(gc, a, b));
      else
        bc = Handle(Geom_BSplineCurve)::DownCast(bc->Copy());
      if (bc->IsPeriodic()) bc->SetNotPeriodic();
    } catch (const Standard_Failure& x) {
      fail(line, where + ": the curve could not be converted to NURBS: " + x.GetMessageString());
    }
    const int n = bc->NbPoles();
    std::vector<Vec3> ctrl;
    std::vector<double> w;
    const bool rational = bc->IsRational();  // as for surfaces
    for (int i = 1; i <= n; ++i) {
      const gp_Pnt p = bc->Pole(i);
      ctrl.emplace_back(p.X(), p.Y(), p.Z());
      w.push_back(rational ? bc->Weight(i) : 1.0);
    }
    TColStd_Array1OfReal kn(1, n + bc->Degree() + 1);
    bc->KnotSequence(kn);
    try {
      out.curve = std::make_shared<NurbsCurve>(bc->Degree(), flat(kn), std::move(ctrl), std::move(w));
    } catch (const ParameterError& x) {
      fail(line, where + ": " + x.what());
    }
    return out;
  }

  std::string path_;
  bool iges_;
  Handle(Interface_InterfaceModel) model_;
  Handle(XSControl_TransferReader) tr_;
};

}  // namespace

CadModel read_cad(const std::string& path) {
  const std::string ext = lower_extension(path);
  const bool iges = ext == "igs" || ext == "iges";
  if (!iges && ext != "stp" && ext != "step")
    throw DataError(path, 0, "unknown CAD format '." + ext + "': expected .igs, .iges, .stp or .step");
  detail::quiet_occt();
  try {
    return Reader(path, iges).read();
  } catch (const Standard_Failure& e) {
    throw DataError(path, 0, std::string("OpenCASCADE failed reading it: ") + e.GetMessageString());
  }
}

}  // namespace bliskrun
