// STEP out: the kernel's NURBS as OCCT B-spline faces and edges, written by
// OCCT's STEPControl_Writer, so the file is what a CAD system would write.
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRep_Builder.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>

#include <cstdio>
#include <mutex>

#include "core/cad/cad.h"
#include "core/cad/occt_setup.h"
#include "core/common/error.h"

namespace bliskrun {

namespace {

// Flat knot vector -> OCCT's distinct knots and multiplicities.
void knots_and_mults(const std::vector<double>& flat, TColStd_Array1OfReal& k,
                     TColStd_Array1OfInteger& m) {
  std::vector<double> ks;
  std::vector<int> ms;
  for (double x : flat) {
    if (!ks.empty() && x == ks.back())
      ++ms.back();
    else {
      ks.push_back(x);
      ms.push_back(1);
    }
  }
  k.Resize(1, static_cast<int>(ks.size()), Standard_False);
  m.Resize(1, static_cast<int>(ms.size()), Standard_False);
  for (size_t i = 0; i < ks.size(); ++i) {
    k(static_cast<int>(i) + 1) = ks[i];
    m(static_cast<int>(i) + 1) = ms[i];
  }
}

Handle(Geom_BSplineSurface) to_occt(const NurbsSurface& s) {
  TColgp_Array2OfPnt poles(1, s.rows(), 1, s.cols());
  TColStd_Array2OfReal w(1, s.rows(), 1, s.cols());
  for (int i = 0; i < s.rows(); ++i)
    for (int j = 0; j < s.cols(); ++j) {
      const Vec3 p = s.control_point(i, j);
      poles(i + 1, j + 1) = gp_Pnt(p.x(), p.y(), p.z());
      w(i + 1, j + 1) = s.weight(i, j);
    }
  TColStd_Array1OfReal ku(1, 1), kv(1, 1);
  TColStd_Array1OfInteger mu(1, 1), mv(1, 1);
  knots_and_mults(s.knots_u(), ku, mu);
  knots_and_mults(s.knots_v(), kv, mv);
  return new Geom_BSplineSurface(poles, w, ku, kv, mu, mv, s.degree_u(), s.degree_v());
}

Handle(Geom_BSplineCurve) to_occt(const NurbsCurve& c) {
  const std::vector<Vec3> p = c.control_points();
  const std::vector<double> w = c.weights();
  TColgp_Array1OfPnt poles(1, static_cast<int>(p.size()));
  TColStd_Array1OfReal ws(1, static_cast<int>(w.size()));
  for (size_t i = 0; i < p.size(); ++i) {
    poles(static_cast<int>(i) + 1) = gp_Pnt(p[i].x(), p[i].y(), p[i].z());
    ws(static_cast<int>(i) + 1) = w[i];
  }
  TColStd_Array1OfReal k(1, 1);
  TColStd_Array1OfInteger m(1, 1);
  knots_and_mults(c.knots(), k, m);
  return new Geom_BSplineCurve(poles, ws, k, m, c.degree());
}

}  // namespace

void write_step(const std::string& path, const std::vector<const NurbsSurface*>& surfaces,
                const std::vector<const NurbsCurve*>& curves, const std::string& schema) {
  if (schema != "AP203" && schema != "AP214IS" && schema != "AP242DIS")
    throw ParameterError("schema", "expected AP203, AP214IS or AP242DIS, got '" + schema + "'");
  // OCCT's writer settings are process-wide statics: one writer at a time.
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  detail::quiet_occt();
  const std::string tmp = path + ".tmp";
  try {
    BRep_Builder b;
    TopoDS_Compound all;
    b.MakeCompound(all);
    for (const NurbsSurface* s : surfaces)
      b.Add(all, BRepBuilderAPI_MakeFace(to_occt(*s), 1e-7).Face());
    for (const NurbsCurve* c : curves) b.Add(all, BRepBuilderAPI_MakeEdge(to_occt(*c)).Edge());
    // The parameters exist once the controller has registered them, and
    // the writer's constructor reads the schema for the file's header
    // (the data follow the value at transfer): so Init, set, construct.
    STEPControl_Controller::Init();
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    Interface_Static::SetCVal("write.step.unit", "MM");
    if (!Interface_Static::SetCVal("write.step.schema", schema.c_str()))
      throw Error(path + ": OpenCASCADE does not know the STEP schema " + schema);
    STEPControl_Writer w;
    if (w.Transfer(all, STEPControl_AsIs) != IFSelect_RetDone)
      throw Error(path + ": OpenCASCADE could not transfer the shapes to STEP");
    if (w.Write(tmp.c_str()) != IFSelect_RetDone) throw Error(path + ": cannot write the STEP file");
  } catch (const Standard_Failure& e) {
    std::remove(tmp.c_str());
    throw Error(path + ": OpenCASCADE failed writing STEP: " + e.GetMessageString());
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw Error(path + ": cannot move the written file into place");
  }
}

}  // namespace bliskrun
