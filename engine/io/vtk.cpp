// VTK XML files for ParaView and OVITO: grains as a .vtu point cloud (radius, velocity, angular
// velocity, force), contacts as .vtp lines (normal and tangential force), grid fields as .vti
// image data, and a .pvd time index. ASCII, so that the files are readable and diffable; each
// written whole or not at all (a temporary file renamed).
#include <sys/stat.h>
#include <unistd.h>
#include <filesystem>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "silt/contacts.hpp"
#include "silt/io.hpp"

namespace silt {
namespace {

// A VTK file is written to a temporary file beside it (make_temp_beside) and renamed onto its name
// once every byte is out: a run killed while writing one left it cut, and a series opened by its
// names failed on it. open_file returns the temporary file's name.
std::string open_file(std::ofstream& out, const std::string& path) {
  const TempFile temp = make_temp_beside(path);
  if (temp.fd < 0) throw IoError("cannot write '" + path + "': " + std::strerror(errno));
  ::close(temp.fd);
  errno = 0;
  out.open(temp.name);
  if (!out) {
    const std::string why = errno != 0 ? std::string(": ") + std::strerror(errno) : std::string();
    std::remove(temp.name.c_str());
    throw IoError("cannot write '" + path + "'" + why);
  }
  out.precision(9);
  return temp.name;
}

// Closes `out`, which open_file opened for `path` on `tmp`, and renames it onto `path`: the last
// buffered bytes go out here, so a full disk shows only now (a check before the close passed on an
// empty file). IoError, the partial file removed, when any write failed.
void close_file(std::ofstream& out, const std::string& path, const std::string& tmp) {
  errno = 0;
  out.close();
  if (out && std::rename(tmp.c_str(), path.c_str()) == 0) return;
  const std::string why = errno != 0 ? std::string(": ") + std::strerror(errno) : std::string();
  std::remove(tmp.c_str());
  throw IoError("cannot write '" + path + "'" + why);
}

void array_header(std::ostream& o, const char* type, const char* name, int components) {
  o << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\"" << components
    << "\" format=\"ascii\">\n          ";
}
const char* kArrayEnd = "\n        </DataArray>\n";

}  // namespace

void write_vti(const std::string& path, const std::vector<GridField>& fields) {
  if (fields.empty()) throw IoError("cannot write '" + path + "': no field");
  const GridField& g = fields.front();
  for (const GridField& f : fields) {
    if (!f.same_grid(g))
      throw IoError("cannot write '" + path + "': field '" + f.name + "' is not on the grid of '" + g.name + "'");
    if (f.components != 1 && f.components != 3)
      throw IoError("cannot write '" + path + "': field '" + f.name + "' has " + std::to_string(f.components) +
                    " components (1 or 3)");
    if (g.nx < 1 || g.ny < 1 || g.nz < 1 || f.value.size() != static_cast<size_t>(g.nx) * g.ny * g.nz * f.components)
      throw IoError("cannot write '" + path + "': field '" + f.name + "' does not fill its grid");
  }
  std::ofstream o;
  const std::string tmp = open_file(o, path);
  // Extents count points: nx cells span points 0 .. nx. The values belong to the cells.
  const std::string extent = "0 " + std::to_string(g.nx) + " 0 " + std::to_string(g.ny) + " 0 " + std::to_string(g.nz);
  o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
    << "  <ImageData WholeExtent=\"" << extent << "\" Origin=\"" << g.lo[0] << ' ' << g.lo[1] << ' ' << g.lo[2]
    << "\" Spacing=\"" << g.h[0] << ' ' << g.h[1] << ' ' << g.h[2] << "\">\n    <Piece Extent=\"" << extent << "\">\n"
    << "      <CellData";
  for (int components : {1, 3})
    for (const GridField& f : fields)
      if (f.components == components) {
        o << (components == 1 ? " Scalars=\"" : " Vectors=\"") << f.name << '"';
        break;
      }
  o << ">\n";
  for (const GridField& f : fields) {
    array_header(o, "Float64", f.name.c_str(), f.components);
    for (double x : f.value) o << x << ' ';
    o << kArrayEnd;
  }
  o << "      </CellData>\n    </Piece>\n  </ImageData>\n</VTKFile>\n";
  close_file(o, path, tmp);
}

VtkWriter::VtkWriter(std::string dir) : dir_(std::move(dir)) {
  make_output_directory(dir_, "VTK");
  // An earlier run's files would mix with this run's in a series opened by their names (the new
  // index.pvd lists only its own): removed, as frames are.
  removed_ = remove_numbered_files(dir_, series());
}

const NumberedSeries& VtkWriter::series() {
  static const NumberedSeries s{{"grains_", ".vtu"}, {"contacts_", ".vtp"}, {"fields_", ".vti"}};
  return s;
}

bool VtkWriter::owns(const std::string& path, const std::string& dir) {
  const std::string name = std::filesystem::path(path).filename().string();
  return (name == "index.pvd" || is_numbered_file(name, series())) && is_in_directory(path, dir);
}

void VtkWriter::write(const Model& m, const State& s, const std::vector<GridField>& fields) {
  // A scene of a fluid alone has no grains and no contacts to write (it wrote two empty files a
  // sample); a scene whose grains have all gone (a silo emptied) goes on with empty ones.
  if (m.n_grains == 0 && !fields.empty()) return write_entry(s.t, "", "", write_fields(fields));
  const int D = m.dim, R = m.rot;
  char name[64];
  std::snprintf(name, sizeof name, "grains_%06lld.vtu", static_cast<long long>(count_));
  const std::string grains = name;
  std::snprintf(name, sizeof name, "contacts_%06lld.vtp", static_cast<long long>(count_));
  const std::string contacts = name;
  {
    std::ofstream o;
    const std::string tmp = open_file(o, dir_ + "/" + grains);
    o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      << "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" << s.n << "\" NumberOfCells=\"" << s.n << "\">\n"
      << "      <Points>\n";
    array_header(o, "Float64", "position", 3);
    for (int64_t i = 0; i < s.n; ++i)
      for (int k = 0; k < 3; ++k) o << (k < D ? s.particle_x[D * i + k] : 0.0) << ' ';
    o << kArrayEnd << "      </Points>\n      <Cells>\n";
    array_header(o, "Int64", "connectivity", 1);
    for (int64_t i = 0; i < s.n; ++i) o << i << ' ';
    o << kArrayEnd;
    array_header(o, "Int64", "offsets", 1);
    for (int64_t i = 0; i < s.n; ++i) o << i + 1 << ' ';
    o << kArrayEnd;
    array_header(o, "UInt8", "types", 1);
    for (int64_t i = 0; i < s.n; ++i) o << "1 ";  // VTK_VERTEX
    o << kArrayEnd << "      </Cells>\n      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
    array_header(o, "Float64", "radius", 1);
    for (int64_t i = 0; i < s.n; ++i) o << s.particle_r[i] << ' ';
    o << kArrayEnd;
    auto vec3 = [&](const char* label, const std::vector<double>& a, int stride, int offset) {
      array_header(o, "Float64", label, 3);
      for (int64_t i = 0; i < s.n; ++i)
        for (int k = 0; k < 3; ++k) {
          const int c = k - offset;  // 2D rotations sit in the z component
          o << (c >= 0 && c < stride ? a[stride * i + c] : 0.0) << ' ';
        }
      o << kArrayEnd;
    };
    if (m.shear.on) {
      // Under Lees-Edwards shear the state holds velocities relative to the shear flow; ParaView
      // users expect the velocity itself, and get the relative one as well.
      std::vector<double> total = s.particle_v;
      for (int64_t i = 0; i < s.n; ++i) total[D * i] += s.shear_rate * (s.particle_x[D * i + 1] - s.box.lo[1]);
      vec3("velocity", total, D, 0);
      vec3("velocity_relative_to_shear_flow", s.particle_v, D, 0);
    } else {
      vec3("velocity", s.particle_v, D, 0);
    }
    vec3("angular_velocity", s.particle_w, R, R == 1 ? 2 : 0);
    // The total force, as p[K].f: the state's sum holds no gravity (a grain at rest on the silo's
    // floor showed m g upwards, the sum over the grains M g).
    std::vector<double> force = s.particle_f;
    for (int64_t i = 0; i < s.n; ++i)
      for (int k = 0; k < D; ++k) force[D * i + k] += m.weight(s.particle_inv_m[i], s.particle_frozen[i], k);
    vec3("force", force, D, 0);
    // The modules' pair forces on each grain (a paste's lubrication: pair_f_lub -> force_lub).
    for (const FieldId id : m.pair_stress_fields) {
      const auto pf = double_field(s, id);
      if (pf.size() != static_cast<size_t>(D * s.n_pairs())) continue;
      std::vector<double> sum(static_cast<size_t>(D * s.n), 0.0);
      for (int64_t i = 0; i < s.n; ++i)
        for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p)
          for (int k = 0; k < D; ++k) {
            sum[D * i + k] += pf[D * p + k];
            sum[D * s.pair_j[p] + k] -= pf[D * p + k];
          }
      std::string label = field_info(id).name;
      if (label.rfind("pair_f_", 0) == 0) label = "force_" + label.substr(7);
      vec3(label.c_str(), sum, D, 0);
    }
    array_header(o, "Int32", "id", 1);
    for (int64_t i = 0; i < s.n; ++i) o << s.particle_id[i] << ' ';
    o << kArrayEnd;
    array_header(o, "UInt8", "frozen", 1);
    for (int64_t i = 0; i < s.n; ++i) o << static_cast<int>(s.particle_frozen[i]) << ' ';
    o << kArrayEnd << "      </PointData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
    close_file(o, dir_ + "/" + grains, tmp);
  }
  {
    // Contacts: one line per touching pair, from i to the image of j next to it.
    struct Line {
      double a[3], b[3], f[3], fn, ft;
    };
    std::vector<Line> lines;
    for (const Contact& c : touching_contacts(s)) {
      Line l{};
      double f2 = 0;
      for (int k = 0; k < 3; ++k) {
        l.a[k] = k < D ? s.particle_x[D * c.i + k] : 0.0;
        l.b[k] = l.a[k] - c.d[k];
        l.f[k] = c.f[k];
        f2 += c.f[k] * c.f[k];
      }
      l.fn = c.fn;
      l.ft = std::sqrt(std::max(0.0, f2 - c.fn * c.fn));
      lines.push_back(l);
    }
    std::ofstream o;
    const std::string tmp = open_file(o, dir_ + "/" + contacts);
    o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      << "  <PolyData>\n    <Piece NumberOfPoints=\"" << 2 * lines.size() << "\" NumberOfLines=\"" << lines.size()
      << "\">\n      <Points>\n";
    array_header(o, "Float64", "position", 3);
    for (const Line& l : lines)
      o << l.a[0] << ' ' << l.a[1] << ' ' << l.a[2] << ' ' << l.b[0] << ' ' << l.b[1] << ' ' << l.b[2] << ' ';
    o << kArrayEnd << "      </Points>\n      <Lines>\n";
    array_header(o, "Int64", "connectivity", 1);
    for (size_t k = 0; k < 2 * lines.size(); ++k) o << k << ' ';
    o << kArrayEnd;
    array_header(o, "Int64", "offsets", 1);
    for (size_t k = 0; k < lines.size(); ++k) o << 2 * (k + 1) << ' ';
    o << kArrayEnd << "      </Lines>\n      <CellData Scalars=\"normal_force\">\n";
    array_header(o, "Float64", "normal_force", 1);
    for (const Line& l : lines) o << l.fn << ' ';
    o << kArrayEnd;
    array_header(o, "Float64", "tangential_force", 1);
    for (const Line& l : lines) o << l.ft << ' ';
    o << kArrayEnd;
    array_header(o, "Float64", "force", 3);
    for (const Line& l : lines) o << l.f[0] << ' ' << l.f[1] << ' ' << l.f[2] << ' ';
    o << kArrayEnd << "      </CellData>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
    close_file(o, dir_ + "/" + contacts, tmp);
  }
  write_entry(s.t, grains, contacts, write_fields(fields));
}

std::string VtkWriter::write_fields(const std::vector<GridField>& fields) {
  if (fields.empty()) return "";
  char name[64];
  std::snprintf(name, sizeof name, "fields_%06lld.vti", static_cast<long long>(count_));
  write_vti(dir_ + "/" + name, fields);
  return name;
}

void VtkWriter::write_entry(double t, const std::string& grains, const std::string& contacts, const std::string& grid) {
  // A series that goes back in time (the shell's `restore` or `reset` between two writes): the
  // index leaves out the entries of the branch left behind, whose files stay, so that the times
  // ParaView reads run forward (they went 0.1, 0.15, 0.2, 0.1, 0.15, 0.2).
  while (!entries_.empty() && !(entries_.back().t < t)) entries_.pop_back();
  entries_.push_back({t, grains, contacts, grid});
  ++count_;
  // The time index, rewritten whole and renamed into place.
  const std::string pvd = dir_ + "/index.pvd";
  {
    std::ofstream o;
    const std::string tmp = open_file(o, pvd);
    o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n";
    for (const Entry& e : entries_) {
      int part = 0;  // the parts a sample has, numbered in this order: grains, contacts, fields
      for (const std::string* file : {&e.grains, &e.contacts, &e.fields})
        if (!file->empty())
          o << "    <DataSet timestep=\"" << e.t << "\" part=\"" << part++ << "\" file=\"" << *file << "\"/>\n";
    }
    o << "  </Collection>\n</VTKFile>\n";
    close_file(o, pvd, tmp);
  }
}

}  // namespace silt
