// The OpenMesh adapter: the only C++ file of relief (see io_openmesh.h).

#include "mesh/io_openmesh.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <queue>
#include <utility>
#include <cctype>
#include <cmath>
#include <cstring>
#include <exception>
#include <fstream>
#include <locale>
#include <new>
#include <cstdio>
#include <locale>
#include <ostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include "base/error.h"
#include "mesh/mesh.h"

namespace {

struct Traits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
    // Colours stay Vec3uc: OpenMesh's exporters cannot cast float colours.
    VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Color |
                     OpenMesh::Attributes::Status);
    FaceAttributes(OpenMesh::Attributes::Status);
};
typedef OpenMesh::TriMesh_ArrayKernelT<Traits> Mesh;

// Reading keeps colours as floats: OpenMesh's importer converts a float
// colour (OBJ, OFF, PLY float) to unsigned char by a cast that is undefined
// behaviour outside [0, 1]; as floats they arrive as written, read_impl
// rejects what is out of range and keeps 8 bits of the rest, as before.
// Integer colours come as c / 255.
struct ReadTraits : Traits {
    typedef OpenMesh::Vec3f Color;
};
typedef OpenMesh::TriMesh_ArrayKernelT<ReadTraits> ReadMesh;

// Routes OpenMesh's global error stream into a string for one call and
// restores it afterwards, whatever happens. It swaps the stream's buffer
// rather than using mostream::connect/disconnect, whose disconnect leaks the
// target it allocated.
class OmerrCapture {
  public:
    OmerrCapture()
        : saved_(omerr().rdbuf(&text_)), log_on_(omlog().is_enabled()),
          out_on_(omout().is_enabled())
    {
        omlog().disable();
        omout().disable();
    }
    ~OmerrCapture()
    {
        omerr().flush();
        omerr().rdbuf(saved_);
        if (log_on_)
            omlog().enable();
        if (out_on_)
            omout().enable();
    }
    OmerrCapture(const OmerrCapture &) = delete;
    OmerrCapture &operator=(const OmerrCapture &) = delete;
    std::string str()
    {
        omerr().flush();
        return text_.str();
    }

  private:
    std::stringbuf text_;
    std::streambuf *saved_;
    bool log_on_, out_on_;
};

size_t count_lines_with(const std::string &text, const char *needle)
{
    size_t n = 0;
    for (size_t at = text.find(needle); at != std::string::npos;
         at = text.find(needle, at + 1))
        ++n;
    return n;
}

// Reads the `label` property whatever integer type the file declared.
template <typename T>
bool copy_label(ReadMesh &mesh, const std::vector<int> &keep_index,
                relief_mesh *out, int char_fix)
{
    OpenMesh::VPropHandleT<T> h;
    if (!mesh.get_property_handle(h, "label"))
        return false;
    for (size_t v = 0; v < mesh.n_vertices(); ++v) {
        int to = keep_index[v];
        if (to < 0)
            continue;
        long value = (long)mesh.property(h, ReadMesh::VertexHandle((int)v));
        if (char_fix)
            value -= '0';
        out->label[to] = value < 0 || value > 255 ? 255 : (uint8_t)value;
    }
    return true;
}

bool has_label(ReadMesh &mesh)
{
    OpenMesh::VPropHandleT<unsigned char> h1;
    OpenMesh::VPropHandleT<signed char> h2;
    OpenMesh::VPropHandleT<char> h3;
    OpenMesh::VPropHandleT<int> h4;
    OpenMesh::VPropHandleT<unsigned int> h5;
    OpenMesh::VPropHandleT<short> h6;
    OpenMesh::VPropHandleT<unsigned short> h7;
    return mesh.get_property_handle(h1, "label") ||
           mesh.get_property_handle(h2, "label") ||
           mesh.get_property_handle(h3, "label") ||
           mesh.get_property_handle(h4, "label") ||
           mesh.get_property_handle(h5, "label") ||
           mesh.get_property_handle(h6, "label") ||
           mesh.get_property_handle(h7, "label");
}

// What OpenMesh said while reading: the faces it rejected for an invalid
// vertex index or for repeating a vertex.
void count_rejects(const std::string &said, relief_om_read_result *res)
{
    res->invalid_index_faces = count_lines_with(said, "invalid vertex index");
    // The PLY reader counts its own rejects: "<n>The reader encountered
    // invalid faces, that could not be added."
    const size_t ply_bad = said.find("The reader encountered invalid faces");
    if (ply_bad != std::string::npos) {
        size_t start = ply_bad;
        while (start > 0 && std::isdigit((unsigned char)said[start - 1]))
            --start;
        res->invalid_index_faces +=
            start < ply_bad ? std::stoul(said.substr(start, ply_bad - start)) : 1;
    }
    res->repeated_vertex_faces = count_lines_with(said, "equal vertices");
}

// Non-manifold faces come back on fresh copies of their vertices, flagged
// "fixed non-manifold"; map each copy back to the file's vertex at the
// same position so the vertex list matches the file. keep_index: the
// file's vertices' new ids (-1 for a copy); original: each vertex's file
// vertex. Returns the count of the file's vertices.
size_t map_nonmanifold_copies(const ReadMesh &mesh, std::vector<int> &keep_index,
                              std::vector<int> &original)
{
    const size_t nv_all = mesh.n_vertices();
    std::vector<size_t> order;
    size_t nv = 0;
    for (size_t v = 0; v < nv_all; ++v) {
        original[v] = (int)v;
        if (!mesh.status(ReadMesh::VertexHandle((int)v)).fixed_nonmanifold())
            keep_index[v] = (int)nv++;
        order.push_back(v);
    }
    if (nv == nv_all)
        return nv;
    auto less = [&](size_t a, size_t b) {
        const ReadMesh::Point &pa = mesh.point(ReadMesh::VertexHandle((int)a));
        const ReadMesh::Point &pb = mesh.point(ReadMesh::VertexHandle((int)b));
        for (int k = 0; k < 3; ++k)
            if (pa[k] != pb[k])
                return pa[k] < pb[k];
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    size_t run = 0;
    while (run < order.size()) {
        size_t end = run + 1;
        const ReadMesh::Point &p0 = mesh.point(ReadMesh::VertexHandle((int)order[run]));
        while (end < order.size() &&
               mesh.point(ReadMesh::VertexHandle((int)order[end])) == p0)
            ++end;
        int first_kept = -1;
        for (size_t i = run; i < end && first_kept < 0; ++i)
            if (keep_index[order[i]] >= 0)
                first_kept = (int)order[i];
        for (size_t i = run; i < end; ++i)
            if (keep_index[order[i]] < 0 && first_kept >= 0)
                original[order[i]] = first_kept;
        run = end;
    }
    return nv;
}

// The kept vertices' positions, colours (as 8 bits; refused outside 0..1)
// and normals into m.
relief_status copy_vertices(const ReadMesh &mesh, const std::vector<int> &keep_index,
                            bool colours, bool normals, relief_mesh *m,
                            const char *path, relief_error *err)
{
    for (size_t v = 0; v < keep_index.size(); ++v) {
        int to = keep_index[v];
        if (to < 0)
            continue;
        ReadMesh::VertexHandle vh((int)v);
        const ReadMesh::Point &p = mesh.point(vh);
        for (int k = 0; k < 3; ++k)
            m->pos[3 * to + k] = p[k];
        if (colours) {
            const ReadMesh::Color &c = mesh.color(vh);
            for (int k = 0; k < 3; ++k) {
                if (!(c[k] >= 0.0f && c[k] <= 1.0f))
                    return relief_fail(err, RELIEF_E_MESH,
                                       "%s: vertex %zu: colour (%g, %g, %g) is outside "
                                       "0..1 (floating-point colours are fractions)",
                                       path, v, (double)c[0], (double)c[1], (double)c[2]);
                // As 8 bits, as relief keeps colours (and writes them).
                m->col[3 * to + k] = std::round(c[k] * 255.0f) / 255.0f;
            }
        }
        if (normals) {
            const ReadMesh::Normal &n = mesh.normal(vh);
            for (int k = 0; k < 3; ++k)
                m->nrm[3 * to + k] = n[k];
        }
    }
    return RELIEF_OK;
}

// The faces into m's triangles (a polygon as a fan), on the file's
// vertices; counts the non-manifold and the split faces.
void copy_faces(ReadMesh &mesh, const std::vector<int> &keep_index,
                const std::vector<int> &original, relief_mesh *m,
                relief_om_read_result *res)
{
    size_t t = 0;
    for (auto f : mesh.faces()) {
        std::vector<uint32_t> corner;
        for (auto vh : mesh.fv_range(f))
            corner.push_back((uint32_t)keep_index[original[vh.idx()]]);
        if (mesh.status(f).fixed_nonmanifold())
            ++res->nonmanifold_faces;
        if (corner.size() > 3)
            ++res->polygon_faces_split;
        for (size_t k = 1; k + 1 < corner.size(); ++k, ++t) {
            m->tri[3 * t] = corner[0];
            m->tri[3 * t + 1] = corner[k];
            m->tri[3 * t + 2] = corner[k + 1];
        }
    }
}

// Numbers in OpenMesh's text formats. OpenMesh reads and writes them through
// C++ streams, which follow their std::locale, never C's setlocale (libstdc++'s
// classic facets convert through the C locale themselves): a program's
// setlocale(LC_ALL, "de_DE.UTF-8") leaves them alone. A C++ program's
// std::locale::global(std::locale("de_DE.UTF-8")) does not: every stream made
// after it, OpenMesh's own included, reads "1.5" as 15 (an ascii PLY's header
// never ends) and writes "1,5", and under en_US "1,234" for 1234. Where
// OpenMesh takes a stream, relief opens it in the classic locale: reading a
// PLY (what OpenMesh's path overload does, in a stream of relief's) and all
// writing. The OFF, OBJ and ascii STL readers parse each line through a
// stringstream of their own (and OFF's takes its options from the path):
// under such a locale they are refused, not misread.

// Does `loc` read numbers as the classic locale: '.' the decimal point, and
// no '.' between groups of digits?
bool classic_numbers(const std::locale &loc)
{
    const std::numpunct<char> &np = std::use_facet<std::numpunct<char>>(loc);
    return np.decimal_point() == '.' && (np.grouping().empty() || np.thousands_sep() != '.');
}

// OpenMesh's read of `path` into `mesh`: a PLY through a classic stream.
bool read_file(ReadMesh &mesh, const char *path, const char *ext, OpenMesh::IO::Options &opt)
{
    if (std::strcmp(ext, ".ply") != 0)
        return OpenMesh::IO::read_mesh(mesh, path, opt);
    std::ifstream in(path, std::ios::binary);
    in.imbue(std::locale::classic());
    return in.is_open() && OpenMesh::IO::read_mesh(mesh, in, ext, opt);
}

/* A std::ostream's bytes into a C stream, whose errors the caller checks
 * (OpenMesh's own file writer does not see a failed flush or close). */
class FileBuf : public std::streambuf {
  public:
    explicit FileBuf(FILE *f) : f_(f) {}

  protected:
    int_type overflow(int_type c) override
    {
        if (traits_type::eq_int_type(c, traits_type::eof()))
            return traits_type::not_eof(c);
        return std::fputc(c, f_) == EOF ? traits_type::eof() : c;
    }
    std::streamsize xsputn(const char *s, std::streamsize n) override
    {
        return (std::streamsize)std::fwrite(s, 1, (size_t)n, f_);
    }

  private:
    FILE *f_;
};

// `m` written into the C stream f as `ext` by OpenMesh, through a classic
// stream (its numbers "0.5" whatever the program's locale).
bool write_file(const Mesh &mesh, FILE *f, const char *ext, OpenMesh::IO::Options opt)
{
    FileBuf buf(f);
    std::ostream os(&buf);
    os.imbue(std::locale::classic());
    if (std::strcmp(ext, ".obj") == 0) // as OpenMesh's OBJ writer sets its own file
        os << std::fixed;
    return OpenMesh::IO::write_mesh(mesh, os, ext, opt, 9) && !os.fail();
}

relief_status read_impl(const char *path, const char *ext, int binary, int ascii_char_label,
                        relief_mesh **out, relief_om_read_result *res, relief_error *err)
{
    ReadMesh mesh;
    mesh.request_vertex_colors();
    mesh.request_vertex_normals();
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexColor |
                                OpenMesh::IO::Options::VertexNormal |
                                OpenMesh::IO::Options::Custom;
    bool ok;
    std::string said;
    if (std::strcmp(ext, ".ply") != 0 && !binary && !classic_numbers(std::locale()))
        return relief_fail(err, RELIEF_E_USAGE, "%s: this program's C++ global locale (%s, "
                           "set by std::locale::global) does not read 0.5 as a half, and "
                           "OpenMesh would misread the numbers of a text %s file in it; keep "
                           "that locale classic, or read a PLY", path,
                           std::locale().name().c_str(), ext);
    {
        OmerrCapture capture;
        ok = read_file(mesh, path, ext, opt);
        said = capture.str();
    }
    std::replace(said.begin(), said.end(), '\n', ' ');
    snprintf(res->messages, sizeof res->messages, "%s", said.c_str());
    if (!ok)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: OpenMesh could not read the file%s%s", path,
                           said.empty() ? "" : ": ", said.c_str());
    count_rejects(said, res);

    std::vector<int> keep_index(mesh.n_vertices(), -1);
    std::vector<int> original(mesh.n_vertices());
    const size_t nv = map_nonmanifold_copies(mesh, keep_index, original);
    size_t nt = 0;
    for (auto f : mesh.faces())
        nt += (size_t)(mesh.valence(f) - 2);
    const bool colours = opt.vertex_has_color() && std::strcmp(ext, ".stl") != 0;
    const bool normals = opt.vertex_has_normal() && std::strcmp(ext, ".stl") != 0;
    const bool labels = has_label(mesh);
    unsigned attrs = 0;
    if (colours)
        attrs |= RELIEF_MESH_COLOURS;
    if (normals)
        attrs |= RELIEF_MESH_NORMALS;
    if (labels)
        attrs |= RELIEF_MESH_LABELS;
    relief_mesh *m = nullptr;
    relief_status st = relief_mesh_create(nv, nt, attrs, &m, err);
    if (st != RELIEF_OK)
        return st;
    st = copy_vertices(mesh, keep_index, colours, normals, m, path, err);
    if (st != RELIEF_OK) {
        relief_mesh_destroy(m);
        return st;
    }
    if (labels) {
        copy_label<unsigned char>(mesh, keep_index, m, ascii_char_label) ||
            copy_label<signed char>(mesh, keep_index, m, ascii_char_label) ||
            copy_label<char>(mesh, keep_index, m, ascii_char_label) ||
            copy_label<int>(mesh, keep_index, m, 0) ||
            copy_label<unsigned int>(mesh, keep_index, m, 0) ||
            copy_label<short>(mesh, keep_index, m, 0) ||
            copy_label<unsigned short>(mesh, keep_index, m, 0);
    }
    copy_faces(mesh, keep_index, original, m, res);
    *out = m;
    return RELIEF_OK;
}


relief_status write_impl(const relief_mesh *m, FILE *f, const char *path, const char *ext,
                         int ascii, relief_error *err)
{
    Mesh mesh;
    const bool colours = m->col && (std::strcmp(ext, ".ply") == 0 ||
                                    std::strcmp(ext, ".off") == 0);
    const bool normals = m->nrm && std::strcmp(ext, ".ply") == 0;
    const bool labels = m->label && std::strcmp(ext, ".ply") == 0;
    mesh.request_vertex_colors();
    mesh.request_vertex_normals();
    OpenMesh::VPropHandleT<int> label;
    if (labels) {
        mesh.add_property(label, "label");
        mesh.property(label).set_persistent(true);
    }
    for (size_t v = 0; v < m->nv; ++v) {
        const double *p = m->pos + 3 * v;
        Mesh::VertexHandle vh = mesh.add_vertex(Mesh::Point(p[0], p[1], p[2]));
        if (colours) {
            const float *c = m->col + 3 * v;
            Mesh::Color uc;
            for (int k = 0; k < 3; ++k)
                uc[k] = (unsigned char)std::lround(
                    std::min(1.0f, std::max(0.0f, c[k])) * 255.0f);
            mesh.set_color(vh, uc);
        }
        if (normals) {
            const double *n = m->nrm + 3 * v;
            mesh.set_normal(vh, Mesh::Normal(n[0], n[1], n[2]));
        }
        if (labels)
            mesh.property(label, vh) = m->label[v];
    }
    std::string said;
    {
        OmerrCapture capture;
        for (size_t t = 0; t < m->nt; ++t) {
            const uint32_t *f = m->tri + 3 * t;
            Mesh::FaceHandle fh = mesh.add_face(Mesh::VertexHandle((int)f[0]),
                                                Mesh::VertexHandle((int)f[1]),
                                                Mesh::VertexHandle((int)f[2]));
            if (!fh.is_valid())
                return relief_fail(err, RELIEF_E_MESH,
                                   "%s: triangle %zu (%u %u %u) would make the "
                                   "mesh non-manifold; OpenMesh cannot store it",
                                   path, t, (unsigned)f[0], (unsigned)f[1],
                                   (unsigned)f[2]);
        }
        OpenMesh::IO::Options opt;
        if (colours)
            opt += OpenMesh::IO::Options::VertexColor;
        if (normals)
            opt += OpenMesh::IO::Options::VertexNormal;
        if (labels)
            opt += OpenMesh::IO::Options::Custom;
        if (!ascii && (std::strcmp(ext, ".ply") == 0 || std::strcmp(ext, ".stl") == 0))
            opt += OpenMesh::IO::Options::Binary;
        if (!write_file(mesh, f, ext, opt)) {
            said = capture.str();
            return relief_fail(err, RELIEF_E_IO, "%s: OpenMesh could not write it%s%s",
                               path, said.empty() ? "" : ": ", said.c_str());
        }
    }
    return RELIEF_OK;
}

relief_status storable_impl(const relief_mesh *m, const uint32_t *extra, size_t n_extra,
                            uint8_t *accepted, relief_error *err)
{
    Mesh mesh;
    OmerrCapture capture; /* add_face's complaints are expected here */
    for (size_t v = 0; v < m->nv; ++v) {
        const double *p = m->pos + 3 * v;
        mesh.add_vertex(Mesh::Point(p[0], p[1], p[2]));
    }
    for (size_t t = 0; t < m->nt; ++t) {
        const uint32_t *f = m->tri + 3 * t;
        if (!mesh.add_face(Mesh::VertexHandle((int)f[0]), Mesh::VertexHandle((int)f[1]),
                           Mesh::VertexHandle((int)f[2])).is_valid())
            return relief_fail(err, RELIEF_E_MESH, "triangle %zu (%u %u %u) of the mesh is "
                               "not manifold already", t, (unsigned)f[0], (unsigned)f[1],
                               (unsigned)f[2]);
    }
    for (size_t t = 0; t < n_extra; ++t) {
        const uint32_t *f = extra + 3 * t;
        accepted[t] = mesh.add_face(Mesh::VertexHandle((int)f[0]), Mesh::VertexHandle((int)f[1]),
                                    Mesh::VertexHandle((int)f[2]))
                          .is_valid();
    }
    return RELIEF_OK;
}


// ------------------------------------------------------------ collapses

struct CollapseGeometry {
    const double *pos, *nrm;
    double max_edge2, cos_fold;
};

double dist2(const double *a, const double *b)
{
    double d = 0.0;
    for (int k = 0; k < 3; ++k)
        d += (a[k] - b[k]) * (a[k] - b[k]);
    return d;
}

// Whether the triangle (a, b, c) (ids) faces within the fold limit of the
// surface's normals at its corners, and is not degenerate.
bool faces_ok(const CollapseGeometry &g, int a, int b, int c)
{
    const double *pa = g.pos + 3 * (size_t)a, *pb = g.pos + 3 * (size_t)b,
                 *pc = g.pos + 3 * (size_t)c;
    double ab[3], ac[3], x[3], ref[3], lx = 0.0, lr = 0.0, d = 0.0;
    for (int k = 0; k < 3; ++k) {
        ab[k] = pb[k] - pa[k];
        ac[k] = pc[k] - pa[k];
        ref[k] = g.nrm[3 * (size_t)a + k] + g.nrm[3 * (size_t)b + k] + g.nrm[3 * (size_t)c + k];
    }
    x[0] = ab[1] * ac[2] - ab[2] * ac[1];
    x[1] = ab[2] * ac[0] - ab[0] * ac[2];
    x[2] = ab[0] * ac[1] - ab[1] * ac[0];
    for (int k = 0; k < 3; ++k) {
        lx += x[k] * x[k];
        lr += ref[k] * ref[k];
        d += x[k] * ref[k];
    }
    // Degenerate: area below 1e-12 of the squared longest edge.
    if (lx <= 1e-24 * std::max(dist2(pa, pb), std::max(dist2(pa, pc), dist2(pb, pc))) *
                     std::max(dist2(pa, pb), std::max(dist2(pa, pc), dist2(pb, pc))) ||
        lr <= 0.0)
        return false;
    return d > g.cos_fold * std::sqrt(lx * lr);
}

// The cost of collapsing h's from-vertex into its to-vertex: the longest
// edge it makes (squared), or infinity when it must not be done.
double collapse_cost(Mesh &mesh, const CollapseGeometry &g, Mesh::HalfedgeHandle h)
{
    const Mesh::VertexHandle v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
    const int iu = u.idx();
    double worst = 0.0;
    // The border stays where it is: a border vertex goes only along it.
    if (mesh.is_boundary(v) && !mesh.is_boundary(mesh.edge_handle(h)))
        return HUGE_VAL;
    if (!mesh.is_collapse_ok(h))
        return HUGE_VAL;
    for (Mesh::VertexHandle w : mesh.vv_range(v)) {
        double e = dist2(g.pos + 3 * (size_t)iu, g.pos + 3 * (size_t)w.idx());
        if (w == u)
            continue;
        if (e > g.max_edge2)
            return HUGE_VAL;
        worst = std::max(worst, e);
    }
    for (Mesh::FaceHandle f : mesh.vf_range(v)) {
        int c[3], n = 0, has_u = 0;
        for (Mesh::VertexHandle w : mesh.fv_range(f)) {
            has_u |= w == u;
            c[n++] = w == v ? iu : w.idx();
        }
        if (!has_u && !faces_ok(g, c[0], c[1], c[2]))
            return HUGE_VAL;
    }
    return worst;
}

// The cheapest collapse of v: *best its halfedge (invalid when none).
double best_collapse(Mesh &mesh, const CollapseGeometry &g, Mesh::VertexHandle v,
                     Mesh::HalfedgeHandle *best)
{
    double cost = HUGE_VAL;
    *best = Mesh::HalfedgeHandle();
    for (Mesh::HalfedgeHandle h : mesh.voh_range(v)) {
        double c = collapse_cost(mesh, g, h);
        if (c < cost || (c == cost && c < HUGE_VAL &&
                         mesh.to_vertex_handle(h).idx() < mesh.to_vertex_handle(*best).idx())) {
            cost = c;
            *best = h;
        }
    }
    return cost;
}

// One Delaunay flip of edge e if it is due and folds nothing; 1 if done.
int flip_if_due(Mesh &mesh, const CollapseGeometry &g, Mesh::EdgeHandle e)
{
    if (mesh.is_boundary(e) || !mesh.is_flip_ok(e))
        return 0;
    const Mesh::HalfedgeHandle h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    const int a = mesh.from_vertex_handle(h0).idx(), b = mesh.to_vertex_handle(h0).idx();
    const int c = mesh.to_vertex_handle(mesh.next_halfedge_handle(h0)).idx();
    const int d = mesh.to_vertex_handle(mesh.next_halfedge_handle(h1)).idx();
    const double *pa = g.pos + 3 * (size_t)a, *pb = g.pos + 3 * (size_t)b,
                 *pc = g.pos + 3 * (size_t)c, *pd = g.pos + 3 * (size_t)d;
    // The angles at c and at d, opposite the edge ab.
    auto angle = [](const double *o, const double *p, const double *q) {
        double u[3], w[3], uu = 0.0, ww = 0.0, uw = 0.0;
        for (int k = 0; k < 3; ++k) {
            u[k] = p[k] - o[k];
            w[k] = q[k] - o[k];
            uu += u[k] * u[k];
            ww += w[k] * w[k];
            uw += u[k] * w[k];
        }
        return std::acos(std::max(-1.0, std::min(1.0, uw / std::sqrt(uu * ww))));
    };
    if (angle(pc, pa, pb) + angle(pd, pa, pb) <= M_PI + 1e-9)
        return 0;
    // h0 runs a -> b in (a, b, c), h1 b -> a in (b, a, d): after the flip
    // the triangles are (a, d, c) and (d, b, c).
    if (dist2(pc, pd) > g.max_edge2 || !faces_ok(g, a, d, c) || !faces_ok(g, d, b, c))
        return 0;
    mesh.flip(e);
    return 1;
}

relief_status collapse_impl(const relief_mesh *m, const double *pos, const double *nrm,
                            uint8_t *remove, double max_edge, uint32_t **tri_out,
                            size_t *nt_out, relief_error *err)
{
    Mesh mesh;
    OmerrCapture capture;
    const CollapseGeometry g = {pos, nrm, max_edge * max_edge, 0.5}; // cos 60 degrees
    typedef std::pair<double, int> Entry; // (cost, vertex): smallest first
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    std::vector<double> queued(m->nv, HUGE_VAL);

    mesh.request_vertex_status();
    mesh.request_edge_status();
    mesh.request_halfedge_status();
    mesh.request_face_status();
    for (size_t v = 0; v < m->nv; ++v)
        mesh.add_vertex(Mesh::Point(0.0, 0.0, 0.0));
    for (size_t t = 0; t < m->nt; ++t) {
        const uint32_t *f = m->tri + 3 * t;
        if (!mesh.add_face(Mesh::VertexHandle((int)f[0]), Mesh::VertexHandle((int)f[1]),
                           Mesh::VertexHandle((int)f[2])).is_valid())
            return relief_fail(err, RELIEF_E_MESH, "triangle %zu (%u %u %u) is not manifold: "
                               "the surface cannot be coarsened", t, (unsigned)f[0],
                               (unsigned)f[1], (unsigned)f[2]);
    }
    for (size_t v = 0; v < m->nv; ++v) {
        Mesh::HalfedgeHandle h;
        if (!remove[v])
            continue;
        queued[v] = best_collapse(mesh, g, Mesh::VertexHandle((int)v), &h);
        if (queued[v] < HUGE_VAL)
            heap.push(Entry(queued[v], (int)v));
    }
    while (!heap.empty()) {
        const Entry top = heap.top();
        const Mesh::VertexHandle v(top.second);
        Mesh::HalfedgeHandle h;
        heap.pop();
        if (mesh.status(v).deleted() || top.first != queued[(size_t)top.second])
            continue; // stale
        queued[(size_t)top.second] = best_collapse(mesh, g, v, &h);
        if (queued[(size_t)top.second] > top.first) { // dearer now: later
            if (queued[(size_t)top.second] < HUGE_VAL)
                heap.push(Entry(queued[(size_t)top.second], top.second));
            continue;
        }
        const Mesh::VertexHandle u = mesh.to_vertex_handle(h);
        mesh.collapse(h);
        queued[(size_t)top.second] = HUGE_VAL;
        // The costs around u changed: requeue the removable ones.
        for (Mesh::VertexHandle w : mesh.vv_range(u)) {
            Mesh::HalfedgeHandle hw;
            const size_t iw = (size_t)w.idx();
            if (!remove[iw] || mesh.status(w).deleted())
                continue;
            queued[iw] = best_collapse(mesh, g, w, &hw);
            if (queued[iw] < HUGE_VAL)
                heap.push(Entry(queued[iw], (int)iw));
        }
    }
    for (size_t v = 0; v < m->nv; ++v)
        remove[v] = mesh.status(Mesh::VertexHandle((int)v)).deleted() ? 1 : 0;
    // Delaunay flips, in edge order, until none is due (bounded: on a
    // curved surface the criterion need not settle).
    for (int pass = 0; pass < 32; ++pass) {
        size_t flips = 0;
        for (size_t e = 0; e < mesh.n_edges(); ++e) {
            const Mesh::EdgeHandle eh((int)e);
            if (!mesh.status(eh).deleted())
                flips += (size_t)flip_if_due(mesh, g, eh);
        }
        if (!flips)
            break;
    }
    {
        size_t nt = 0;
        uint32_t *tri = (uint32_t *)std::malloc((mesh.n_faces() + 1) * 3 * sizeof *tri);
        if (!tri)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a coarse level's triangles");
        for (size_t t = 0; t < mesh.n_faces(); ++t) {
            const Mesh::FaceHandle fh((int)t);
            if (mesh.status(fh).deleted())
                continue;
            int k = 0;
            for (Mesh::VertexHandle w : mesh.fv_range(fh))
                tri[3 * nt + (size_t)k++] = (uint32_t)w.idx();
            ++nt;
        }
        *tri_out = tri;
        *nt_out = nt;
    }
    return RELIEF_OK;
}

} // namespace

extern "C" relief_status relief_om_storable(const relief_mesh *m, const uint32_t *extra,
                                            size_t n_extra, uint8_t *accepted,
                                            relief_error *err)
{
    try {
        return storable_impl(m, extra, n_extra, accepted, err);
    } catch (const std::bad_alloc &) {
        return relief_fail(err, RELIEF_E_NOMEM, "out of memory while checking triangles");
    } catch (const std::exception &e) {
        return relief_fail(err, RELIEF_E_INTERNAL, "OpenMesh failed: %s", e.what());
    } catch (...) {
        return relief_fail(err, RELIEF_E_INTERNAL, "unknown exception in OpenMesh");
    }
}

extern "C" relief_status relief_om_read(const char *path, const char *ext, int binary,
                                        int ascii_char_label, relief_mesh **out,
                                        relief_om_read_result *res,
                                        relief_error *err)
{
    try {
        *res = relief_om_read_result();
        return read_impl(path, ext, binary, ascii_char_label, out, res, err);
    } catch (const std::bad_alloc &) {
        return relief_fail(err, RELIEF_E_NOMEM, "%s: out of memory while reading",
                           path);
    } catch (const std::exception &e) {
        return relief_fail(err, RELIEF_E_PARSE, "%s: OpenMesh failed: %s", path,
                           e.what());
    } catch (...) {
        return relief_fail(err, RELIEF_E_INTERNAL,
                           "%s: unknown exception in OpenMesh", path);
    }
}

extern "C" relief_status relief_om_write(const relief_mesh *m, FILE *f, const char *path,
                                         const char *ext, int ascii,
                                         relief_error *err)
{
    try {
        return write_impl(m, f, path, ext, ascii, err);
    } catch (const std::bad_alloc &) {
        return relief_fail(err, RELIEF_E_NOMEM, "%s: out of memory while writing",
                           path);
    } catch (const std::exception &e) {
        return relief_fail(err, RELIEF_E_IO, "%s: OpenMesh failed: %s", path,
                           e.what());
    } catch (...) {
        return relief_fail(err, RELIEF_E_INTERNAL,
                           "%s: unknown exception in OpenMesh", path);
    }
}

extern "C" relief_status relief_om_collapse(const relief_mesh *m, const double *pos,
                                           const double *nrm, uint8_t *remove, double max_edge,
                                           uint32_t **tri, size_t *nt, relief_error *err)
{
    try {
        return collapse_impl(m, pos, nrm, remove, max_edge, tri, nt, err);
    } catch (const std::bad_alloc &) {
        return relief_fail(err, RELIEF_E_NOMEM, "out of memory while coarsening a surface");
    } catch (const std::exception &e) {
        return relief_fail(err, RELIEF_E_INTERNAL, "OpenMesh failed: %s", e.what());
    } catch (...) {
        return relief_fail(err, RELIEF_E_INTERNAL, "unknown exception in OpenMesh");
    }
}
