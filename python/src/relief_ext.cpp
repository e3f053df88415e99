// relief's Python extension (_relief): thin calls into librelief's public
// API (include/relief/*.h). The package python/relief/__init__.py checks
// and converts the arguments (dtype, shape, contiguity) and raises
// ReliefError; here every call takes arrays of exactly the types it needs
// and returns (status, message, ...): status 0 is success, any other is a
// relief_status whose message names what went wrong.
//
// Ownership: an engine writes in place into an array the package made for
// the result (image_fill, depth_fill), or its output mesh is copied into
// new arrays owned by Python (complete_mesh, complete_points, read_mesh).
// The GIL is released while an engine runs; the progress callback takes it
// back at most every 50 ms to call the user's function, its cancel event's
// is_set() and to look for Ctrl-C (KeyboardInterrupt cancels the run:
// nothing is written). relief.cancel_all() and the interpreter's exit
// cancel without the GIL (calls in flight, below).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "relief/relief.h"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

template <typename T> using carray = nb::ndarray<nb::numpy, T, nb::c_contig, nb::device::cpu>;

// ------------------------------------------------------- calls in flight
//
// The extension's only global state (the library has none): what the
// interpreter's exit and relief.cancel_all() must know of the calls.
//
// At exit, Python runs the package's atexit hook (at_exit below) before it
// finalises, while daemon threads still live. A thread that needs the GIL
// after finalisation began is ended by pthread_exit, whose forced unwind
// through our C++ frames (nanobind's GIL guards, its dispatch) ends in
// std::terminate or a fatal error: the exit 134 of issue 60. So no thread
// may be inside a call of this module, able to take the GIL again, when
// the hook returns. The hook sets `exiting`: no call starts any more, a
// call's progress cancels it without taking the GIL, and a call whose
// library function returns parks its thread (until the process ends)
// instead of taking the GIL back. The hook then waits, without the GIL,
// until every call has left or parked: those in the user's Python (a
// progress callback) or holding the GIL are always waited for; those in
// the library without the GIL only up to a timeout (a call without
// progress steps, as find_occluders, runs to its end and then parks).

struct calls_state {
    std::mutex mu;
    std::condition_variable changed;
    size_t active = 0;  // calls in this module, not parked
    size_t in_library = 0; // of them, in the library without the GIL
    std::atomic<bool> exiting{false}; // written under mu, read without it too
};

// Never deleted (and replaced, not reset, in a forked child): a parked
// thread may hold it while the process exits, and a static destructor
// would race it.
calls_state *g_calls = new calls_state;

// relief.cancel_all() adds 1; a call remembers the value it started under
// and is cancelled at its next progress when the value has changed.
std::atomic<uint64_t> g_cancel_generation{0};

bool interpreter_finalizing()
{
#if PY_VERSION_HEX >= 0x030D0000
    return Py_IsFinalizing() != 0;
#else
    return _Py_IsFinalizing() != 0;
#endif
}

// Whether a thread without the GIL must stay away from Python: the hook
// has run, or (an embedder's exit without it) finalisation has begun.
bool must_not_touch_python()
{
    return g_calls->exiting.load() || interpreter_finalizing();
}

[[noreturn]] void park_thread()
{
    for (;;)
        std::this_thread::sleep_for(std::chrono::hours(1));
}

// One call of this module, from its start to its return (GIL held at
// both). Refused (`refused`) once the interpreter is exiting.
struct call_scope {
    calls_state *c = g_calls;
    bool refused = false;

    call_scope()
    {
        std::lock_guard<std::mutex> lock(c->mu);
        refused = c->exiting.load();
        if (!refused)
            ++c->active;
    }
    ~call_scope()
    {
        if (refused)
            return;
        {
            std::lock_guard<std::mutex> lock(c->mu);
            --c->active;
        }
        c->changed.notify_all();
    }
    call_scope(const call_scope &) = delete;
    call_scope &operator=(const call_scope &) = delete;
};

// The library's `call` (which never throws) without the GIL, within
// `scope`. Refused (RELIEF_E_CANCELLED in err) once the interpreter is
// exiting; parks instead of taking the GIL back when it began exiting
// meanwhile.
template <typename F> relief_status without_gil(call_scope &scope, relief_error *err, F &&call)
{
    calls_state *c = scope.c;
    {
        std::lock_guard<std::mutex> lock(c->mu);
        if (scope.refused || c->exiting.load()) {
            err->status = RELIEF_E_CANCELLED;
            snprintf(err->message, sizeof err->message,
                     "cancelled: the Python interpreter is exiting");
            return RELIEF_E_CANCELLED;
        }
        ++c->in_library;
    }
    PyThreadState *ts = PyEval_SaveThread();
    const relief_status s = call();
    bool park;
    {
        std::lock_guard<std::mutex> lock(c->mu);
        --c->in_library;
        park = must_not_touch_python();
        if (park)
            --c->active;
    }
    c->changed.notify_all();
    if (park)
        park_thread();
    PyEval_RestoreThread(ts);
    return s;
}

// From the library into Python (a progress callback about to take the
// GIL): false, leaving the call in the library, when the interpreter is
// exiting.
bool leave_library(calls_state *c)
{
    std::lock_guard<std::mutex> lock(c->mu);
    if (must_not_touch_python())
        return false;
    --c->in_library;
    return true;
}

void back_to_library(calls_state *c)
{
    std::lock_guard<std::mutex> lock(c->mu);
    ++c->in_library;
}

// The atexit hook: refuses new calls, cancels those in flight and waits
// for them (see above), `timeout` seconds at most for those in the
// library. Ctrl-C ends the wait (KeyboardInterrupt). Returns how many
// calls are still running in the library.
size_t at_exit(double timeout)
{
    calls_state *c = g_calls;
    {
        std::lock_guard<std::mutex> lock(c->mu);
        c->exiting = true;
    }
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
    for (;;) {
        bool done;
        {
            nb::gil_scoped_release nogil; // a progress callback may be waiting for it
            std::unique_lock<std::mutex> lock(c->mu);
            auto settled = [&] {
                return c->active == 0 ||
                       (c->active == c->in_library && std::chrono::steady_clock::now() >= until);
            };
            c->changed.wait_for(lock, std::chrono::milliseconds(100), settled);
            done = settled();
        }
        if (done)
            break;
        if (PyErr_CheckSignals() != 0)
            throw nb::python_error();
    }
    std::lock_guard<std::mutex> lock(c->mu);
    return c->active;
}

// os.register_at_fork's after_in_child: the threads of the parent's calls
// do not exist here.
void after_fork_in_child()
{
    g_calls = new calls_state;
}

// --------------------------------------------------------------- progress

struct progress_state {
    calls_state *calls = nullptr;
    nb::object fn;     // the user's callable, or None
    nb::object cancel; // an object with is_set() (threading.Event), or None
    uint64_t generation = 0; // g_cancel_generation when the call started
    const char *cancelled_by = nullptr; // what cancelled, when not fn
    std::unique_ptr<nb::python_error> error; // raised in fn or is_set, or KeyboardInterrupt
    std::chrono::steady_clock::time_point last;
    bool started = false;
};

// In Python, GIL held: Ctrl-C, the cancel event, the user's function.
int progress_in_python(progress_state *st, double fraction)
{
    nb::gil_scoped_acquire gil;
    try {
        if (PyErr_CheckSignals() != 0)
            throw nb::python_error();
        if (!st->cancel.is_none() && nb::bool_(st->cancel.attr("is_set")())) {
            st->cancelled_by = "the cancel event";
            return 1;
        }
        if (!st->fn.is_none() && nb::bool_(st->fn(fraction)))
            return 1; // a true answer cancels, as the C callback's non-zero
    } catch (nb::python_error &e) {
        st->error = std::make_unique<nb::python_error>(std::move(e));
        return 1;
    }
    return 0;
}

extern "C" int progress_cb(void *ctx, double fraction)
{
    auto *st = static_cast<progress_state *>(ctx);
    // These two need no GIL, and the exit's must not take it.
    if (must_not_touch_python()) {
        st->cancelled_by = "the Python interpreter's exit";
        return 1;
    }
    if (g_cancel_generation.load() != st->generation) {
        st->cancelled_by = "relief.cancel_all()";
        return 1;
    }
    const auto now = std::chrono::steady_clock::now();
    if (st->started && fraction < 1.0 && now - st->last < std::chrono::milliseconds(50))
        return 0;
    st->started = true;
    st->last = now;
    if (!leave_library(st->calls)) {
        st->cancelled_by = "the Python interpreter's exit";
        return 1;
    }
    const int answer = progress_in_python(st, fraction);
    back_to_library(st->calls);
    return answer;
}

// The user's progress and cancel event, from the package.
struct progress_args {
    nb::object fn, cancel;
};

// Runs `call` without the GIL, within `scope`, with progress into each of
// `runs`; rethrows what the user's callback raised (or Ctrl-C's
// KeyboardInterrupt); a cancel by cancel_all, the event or the exit says
// so in err's message.
template <typename F>
relief_status run_released(call_scope &scope, std::initializer_list<relief_run_options *> runs,
                           const progress_args &pa, relief_error *err, F &&call)
{
    progress_state st;
    st.calls = scope.c;
    st.fn = pa.fn;
    st.cancel = pa.cancel;
    st.generation = g_cancel_generation.load();
    for (relief_run_options *run : runs) {
        run->progress = progress_cb;
        run->progress_ctx = &st;
    }
    relief_status s = without_gil(scope, err, call);
    if (st.error)
        throw *st.error;
    if (s == RELIEF_E_CANCELLED && st.cancelled_by) {
        std::string m = err->message;
        const std::string said = "the progress callback";
        const size_t at = m.find(said);
        m = at != std::string::npos ? m.replace(at, said.size(), st.cancelled_by)
                                    : m + " (by " + st.cancelled_by + ")";
        snprintf(err->message, sizeof err->message, "%s", m.c_str());
    }
    return s;
}

// ------------------------------------------------------------- parameters

// The keyword arguments, as text, into an engine's params through its
// table (relief_param_set); the strings stay alive for PATH parameters.
struct param_setter {
    std::vector<std::string> kept;
    relief_error err{};

    relief_status set(void *params, const relief_param *table, size_t count,
                      const nb::dict &kw, const char *engine)
    {
        for (auto item : kw) {
            const std::string name = nb::cast<std::string>(item.first);
            const relief_param *p = relief_param_find(table, count, name.c_str());
            if (!p) {
                std::string known;
                for (size_t i = 0; i < count; ++i)
                    known += (i ? ", " : "") + std::string(table[i].name);
                snprintf(err.message, sizeof err.message,
                         "%s: unknown parameter '%s' (known: %s)", engine, name.c_str(),
                         known.c_str());
                return err.status = RELIEF_E_USAGE;
            }
            kept.push_back(nb::cast<std::string>(item.second));
            if (relief_param_set(params, p, kept.back().c_str(), &err) != RELIEF_OK)
                return err.status;
        }
        return RELIEF_OK;
    }
};

nb::object json_or_none(const char *json)
{
    return json ? nb::object(nb::str(json)) : nb::none();
}

// ----------------------------------------------------------------- meshes

template <typename T> nb::object new_array(const T *src, size_t rows, size_t cols)
{
    if (!src)
        return nb::none();
    T *buf = new T[rows * cols + 1];
    std::memcpy(buf, src, rows * cols * sizeof(T));
    nb::capsule owner(buf, [](void *p) noexcept { delete[] static_cast<T *>(p); });
    const size_t shape[2] = {rows, cols};
    return nb::cast(carray<T>(buf, cols == 1 ? 1 : 2, shape, owner));
}

// The mesh's arrays: (vertices, faces, colours, normals, labels); None for
// what it lacks.
nb::tuple mesh_arrays(relief_mesh *m)
{
    const size_t nv = relief_mesh_vertex_count(m), nt = relief_mesh_triangle_count(m);
    return nb::make_tuple(new_array(relief_mesh_positions(m), nv, 3),
                          new_array(relief_mesh_triangles(m), nt, 3),
                          new_array(relief_mesh_colours(m), nv, 3),
                          new_array(relief_mesh_normals(m), nv, 3),
                          new_array(relief_mesh_labels(m), nv, 1));
}

// A relief_mesh from the package's arrays (checked there: shapes agree).
relief_status make_mesh(const carray<const double> &v, nb::object faces, nb::object colours,
                        nb::object normals, nb::object labels, relief_mesh **out,
                        relief_error *err)
{
    const size_t nv = v.shape(0);
    const size_t nt = faces.is_none() ? 0 : nb::cast<carray<const uint32_t>>(faces).shape(0);
    unsigned attrs = (colours.is_none() ? 0u : unsigned(RELIEF_MESH_COLOURS)) |
                     (normals.is_none() ? 0u : unsigned(RELIEF_MESH_NORMALS)) |
                     (labels.is_none() ? 0u : unsigned(RELIEF_MESH_LABELS));
    relief_status s = relief_mesh_create(nv, nt, attrs, out, err);
    if (s != RELIEF_OK)
        return s;
    std::memcpy(relief_mesh_positions(*out), v.data(), nv * 3 * sizeof(double));
    if (nt)
        std::memcpy(relief_mesh_triangles(*out), nb::cast<carray<const uint32_t>>(faces).data(),
                    nt * 3 * sizeof(uint32_t));
    if (!colours.is_none())
        std::memcpy(relief_mesh_colours(*out), nb::cast<carray<const float>>(colours).data(),
                    nv * 3 * sizeof(float));
    if (!normals.is_none())
        std::memcpy(relief_mesh_normals(*out), nb::cast<carray<const double>>(normals).data(),
                    nv * 3 * sizeof(double));
    if (!labels.is_none())
        std::memcpy(relief_mesh_labels(*out), nb::cast<carray<const uint8_t>>(labels).data(),
                    nv);
    return RELIEF_OK;
}

// ---------------------------------------------------------------- engines

// The library's memory check from an array's shape (before the package
// copies it): (status, message). A side over the library's largest is
// said here, as the library says it, since it may not fit an int.
nb::tuple image_fill_check_memory(size_t height, size_t width, size_t channels, nb::dict kw)
{
    relief_image_fill_params p = relief_image_fill_params_default();
    param_setter ps;
    size_t count = 0;
    const relief_param *table = relief_image_fill_param_table(&count);
    relief_error err{};
    relief_status s = ps.set(&p, table, count, kw, "image_fill");
    if (s != RELIEF_OK)
        return nb::make_tuple(int(s), std::string(ps.err.message));
    if (width > RELIEF_IMAGE_MAX_SIDE || height > RELIEF_IMAGE_MAX_SIDE) {
        const bool w = width > RELIEF_IMAGE_MAX_SIDE;
        snprintf(err.message, sizeof err.message,
                 "image: %s %zu out of range: expected 1..%d pixels", w ? "width" : "height",
                 w ? width : height, RELIEF_IMAGE_MAX_SIDE);
        return nb::make_tuple(int(RELIEF_E_RANGE), std::string(err.message));
    }
    s = relief_image_fill_check_memory(int(width), int(height), int(channels), &p, &err);
    return nb::make_tuple(int(s), std::string(err.message));
}

nb::tuple depth_fill_check_memory(size_t height, size_t width, nb::dict kw)
{
    relief_depth_fill_params p = relief_depth_fill_params_default();
    param_setter ps;
    size_t count = 0;
    const relief_param *table = relief_depth_fill_param_table(&count);
    relief_error err{};
    relief_status s = ps.set(&p, table, count, kw, "depth_fill");
    if (s != RELIEF_OK)
        return nb::make_tuple(int(s), std::string(ps.err.message));
    if (width > RELIEF_DEPTH_MAX_SIDE || height > RELIEF_DEPTH_MAX_SIDE) {
        const bool w = width > RELIEF_DEPTH_MAX_SIDE;
        snprintf(err.message, sizeof err.message, "frame %s %zu out of range: expected 1..%d",
                 w ? "width" : "height", w ? width : height, RELIEF_DEPTH_MAX_SIDE);
        return nb::make_tuple(int(RELIEF_E_RANGE), std::string(err.message));
    }
    s = relief_depth_fill_check_memory(int(width), int(height), &p, &err);
    return nb::make_tuple(int(s), std::string(err.message));
}

// image: H x W x C (C 1 to 4) uint8 or uint16, filled in place on success;
// mask: H x W uint8, non-zero = fill.
nb::tuple image_fill(nb::ndarray<nb::numpy, nb::c_contig, nb::device::cpu> image,
                     carray<const uint8_t> mask, nb::dict kw, nb::object progress,
                     nb::object cancel)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_image_fill_params p = relief_image_fill_params_default();
    param_setter ps;
    size_t count = 0;
    const relief_param *table = relief_image_fill_param_table(&count);
    if (ps.set(&p, table, count, kw, "image_fill") != RELIEF_OK)
        return nb::make_tuple(int(ps.err.status), std::string(ps.err.message), nb::none());
    relief_image img{int(image.shape(1)), int(image.shape(0)),
                     int(image.ndim() == 3 ? image.shape(2) : 1), int(image.dtype().bits), 0,
                     image.data()};
    relief_image m{int(mask.shape(1)), int(mask.shape(0)), 1, 8, 0,
                   const_cast<uint8_t *>(mask.data())};
    relief_image_fill_report rep;
    std::memset(&rep, 0, sizeof rep);
    relief_error err{};
    relief_status s = run_released(scope, {&p.run}, {progress, cancel}, &err, [&] {
        return relief_image_fill(&img, &m, &p, &rep, &err);
    });
    nb::object json = s == RELIEF_OK ? json_or_none(rep.json) : nb::none();
    relief_image_fill_report_free(&rep);
    return nb::make_tuple(int(s), std::string(err.message), json);
}

// z: H x W float32 (NaN where missing), filled in place on success; mask:
// H x W uint8 or None; colour: H x W x 3 uint8 or None (the layers' guide).
// The values are depths (a PFM's disparities come only from its reader).
nb::tuple depth_fill(carray<float> z, nb::object mask, nb::object colour, nb::dict kw,
                     nb::object progress, nb::object cancel)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_depth_fill_params p = relief_depth_fill_params_default();
    param_setter ps;
    size_t count = 0;
    const relief_param *table = relief_depth_fill_param_table(&count);
    if (ps.set(&p, table, count, kw, "depth_fill") != RELIEF_OK)
        return nb::make_tuple(int(ps.err.status), std::string(ps.err.message), nb::none());
    relief_depth_image f;
    std::memset(&f, 0, sizeof f);
    f.width = int(z.shape(1)), f.height = int(z.shape(0)), f.z = z.data();
    f.format = RELIEF_DEPTH_PNG16;
    if (!colour.is_none())
        f.rgb = const_cast<uint8_t *>(nb::cast<carray<const uint8_t>>(colour).data());
    relief_image m{f.width, f.height, 1, 8, 0, nullptr};
    if (!mask.is_none())
        m.data = const_cast<uint8_t *>(nb::cast<carray<const uint8_t>>(mask).data());
    relief_depth_fill_report rep;
    std::memset(&rep, 0, sizeof rep);
    relief_error err{};
    relief_status s = run_released(scope, {&p.run}, {progress, cancel}, &err, [&] {
        return relief_depth_fill(&f, m.data ? &m : nullptr, &p, &rep, &err);
    });
    nb::object json = s == RELIEF_OK ? json_or_none(rep.json) : nb::none();
    relief_depth_fill_report_free(&rep);
    return nb::make_tuple(int(s), std::string(err.message), json);
}

// An RGB-D frame over the package's arrays: z H x W float32 (NaN where
// missing), xyz H x W x 3 float32 or None, rgb H x W x 3 uint8.
relief_depth_image rgbd_frame(float *z, nb::object xyz, uint8_t *rgb, size_t h, size_t w)
{
    relief_depth_image f;
    std::memset(&f, 0, sizeof f);
    f.width = int(w), f.height = int(h), f.z = z, f.rgb = rgb;
    f.format = RELIEF_DEPTH_PNG16; // depths, not a PFM's disparities
    if (!xyz.is_none())
        f.xyz = nb::cast<carray<float>>(xyz).data();
    return f;
}

// The neighbouring views: colours (each h x w x 3 uint8, its own size) and
// poses (each 3 x 4 float64, then 4 float64: the view's fx, fy, cx, cy, all
// 0 for the frame's camera), lists of the same length (checked by the
// package).
std::vector<relief_occluder_view> views_of(const nb::list &colours, const nb::list &poses)
{
    std::vector<relief_occluder_view> v(nb::len(colours));
    for (size_t k = 0; k < v.size(); ++k) {
        auto c = nb::cast<carray<const uint8_t>>(colours[k]);
        auto m = nb::cast<carray<const double>>(poses[k]);
        std::memset(&v[k], 0, sizeof v[k]);
        v[k].width = int(c.shape(1)), v[k].height = int(c.shape(0)), v[k].rgb = c.data();
        std::memcpy(v[k].pose, m.data(), sizeof v[k].pose);
        std::memcpy(v[k].intrinsics, m.data() + 12, sizeof v[k].intrinsics);
    }
    return v;
}

// (status, message, report, mask H x W uint8: 1 on the occluders).
nb::tuple find_occluders(carray<float> z, nb::object xyz, carray<uint8_t> rgb, nb::list colours,
                         nb::list poses, nb::dict kw)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_occluder_params p = relief_occluder_params_default();
    param_setter ps;
    size_t count = 0;
    const relief_param *table = relief_occluder_param_table(&count);
    if (ps.set(&p, table, count, kw, "find_occluders") != RELIEF_OK)
        return nb::make_tuple(int(ps.err.status), std::string(ps.err.message), nb::none(),
                              nb::none());
    relief_depth_image f = rgbd_frame(z.data(), xyz, rgb.data(), z.shape(0), z.shape(1));
    std::vector<relief_occluder_view> views = views_of(colours, poses);
    p.views = views.empty() ? nullptr : views.data(), p.n_views = int(views.size());
    relief_image mask{0, 0, 0, 0, 0, nullptr};
    relief_occluder_report rep;
    std::memset(&rep, 0, sizeof rep);
    relief_error err{};
    relief_status s =
        without_gil(scope, &err, [&] { return relief_find_occluders(&f, &p, &mask, &rep, &err); });
    nb::object json = s == RELIEF_OK ? json_or_none(rep.json) : nb::none(), m = nb::none();
    if (s == RELIEF_OK) {
        std::vector<uint8_t> bits(size_t(f.width) * f.height);
        for (size_t i = 0; i < bits.size(); ++i)
            bits[i] = static_cast<const uint8_t *>(mask.data)[i] != 0;
        m = new_array(bits.data(), size_t(f.height), size_t(f.width));
    }
    relief_image_free(&mask);
    relief_occluder_report_free(&rep);
    return nb::make_tuple(int(s), std::string(err.message), json, m);
}

// The removal in place on z, xyz (or None) and rgb; mask H x W uint8 or
// None (found). (status, message, report, the mask used).
nb::tuple remove_occluders(carray<float> z, nb::object xyz, carray<uint8_t> rgb, nb::object mask,
                           nb::list colours, nb::list poses, nb::dict kw, nb::dict colour_kw,
                           nb::dict depth_kw, nb::object cancel)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_remove_params p = relief_remove_params_default();
    param_setter ps;
    size_t nf = 0, nc = 0, nd = 0;
    const relief_param *tf = relief_occluder_param_table(&nf);
    const relief_param *tc = relief_image_fill_param_table(&nc);
    const relief_param *td = relief_depth_fill_param_table(&nd);
    if (ps.set(&p.find, tf, nf, kw, "remove_occluders") != RELIEF_OK ||
        ps.set(&p.colour, tc, nc, colour_kw, "remove_occluders colour") != RELIEF_OK ||
        ps.set(&p.depth, td, nd, depth_kw, "remove_occluders depth") != RELIEF_OK)
        return nb::make_tuple(int(ps.err.status), std::string(ps.err.message), nb::none(),
                              nb::none());
    relief_depth_image f = rgbd_frame(z.data(), xyz, rgb.data(), z.shape(0), z.shape(1));
    std::vector<relief_occluder_view> views = views_of(colours, poses);
    p.find.views = views.empty() ? nullptr : views.data(), p.find.n_views = int(views.size());
    relief_image m{f.width, f.height, 1, 8, 0, nullptr};
    if (!mask.is_none())
        m.data = const_cast<uint8_t *>(nb::cast<carray<const uint8_t>>(mask).data());
    relief_remove_report rep;
    std::memset(&rep, 0, sizeof rep);
    relief_error err{};
    // The two fills' progress: no fraction for the user (each goes 0 to 1),
    // but cancel_all, the event, Ctrl-C and the exit reach them.
    relief_status s = run_released(scope, {&p.colour.run, &p.depth.run}, {nb::none(), cancel}, &err,
                                   [&] {
        return relief_remove_occluders(&f, m.data ? &m : nullptr, &p, &rep, &err);
    });
    nb::object json = s == RELIEF_OK ? json_or_none(rep.json) : nb::none(), used = nb::none();
    if (s == RELIEF_OK)
        used = new_array(rep.mask, size_t(f.height), size_t(f.width));
    relief_remove_report_free(&rep);
    return nb::make_tuple(int(s), std::string(err.message), json, used);
}

// A mesh engine's call (relief_complete, relief_complete_points): its
// params through its table, the input mesh from the arrays, the run
// without the GIL; (status, message, report, (vertices, faces, colours,
// normals, labels)).
template <typename Params, typename Report>
nb::tuple mesh_engine(const char *engine, Params p, const relief_param *table, size_t count,
                      const nb::dict &kw, const progress_args &pa,
                      const carray<const double> &v,
                      nb::object faces, nb::object colours, nb::object normals,
                      nb::object labels,
                      relief_status (*call)(const relief_mesh *, const Params *, relief_mesh **,
                                            Report *, relief_error *),
                      void (*free_report)(Report *))
{
    call_scope scope; // first: it outlives everything the call holds
    param_setter ps;
    if (ps.set(&p, table, count, kw, engine) != RELIEF_OK)
        return nb::make_tuple(int(ps.err.status), std::string(ps.err.message), nb::none(),
                              nb::none());
    relief_error err{};
    relief_mesh *in = nullptr, *out = nullptr;
    relief_status s = make_mesh(v, faces, colours, normals, labels, &in, &err);
    Report rep;
    std::memset(&rep, 0, sizeof rep);
    if (s == RELIEF_OK)
        s = run_released(scope, {&p.run}, pa, &err,
                         [&] { return call(in, &p, &out, &rep, &err); });
    relief_mesh_destroy(in);
    nb::object json = nb::none(), arrays = nb::none();
    if (s == RELIEF_OK) {
        json = json_or_none(rep.json);
        arrays = mesh_arrays(out);
    }
    free_report(&rep);
    relief_mesh_destroy(out);
    return nb::make_tuple(int(s), std::string(err.message), json, arrays);
}

nb::tuple complete_mesh(carray<const double> v, nb::object faces, nb::object colours,
                        nb::dict kw, nb::object progress, nb::object cancel)
{
    size_t count = 0;
    const relief_param *table = relief_complete_param_table(&count);
    return mesh_engine("complete_mesh", relief_complete_params_default(), table, count, kw,
                       {progress, cancel}, v, faces, colours, nb::none(), nb::none(),
                       relief_complete, relief_complete_report_free);
}

nb::tuple complete_points(carray<const double> v, nb::object faces, nb::object colours,
                          nb::object normals, nb::object labels, nb::dict kw,
                          nb::object progress, nb::object cancel)
{
    size_t count = 0;
    const relief_param *table = relief_complete_points_param_table(&count);
    return mesh_engine("complete_points", relief_complete_points_params_default(), table, count,
                       kw, {progress, cancel}, v, faces, colours, normals, labels,
                       relief_complete_points, relief_complete_points_report_free);
}

// depth-fill on a mesh (the six depth images of its box), no truth.
relief_status depth_fill_mesh_call(const relief_mesh *in, const relief_depth_fill_params *p,
                                   relief_mesh **out, relief_depth_fill_report *rep,
                                   relief_error *err)
{
    return relief_depth_fill_mesh(in, p, nullptr, out, rep, err);
}

nb::tuple fill_mesh_holes(carray<const double> v, nb::object faces, nb::object colours,
                          nb::dict kw, nb::object progress, nb::object cancel)
{
    size_t count = 0;
    const relief_param *table = relief_depth_fill_param_table(&count);
    return mesh_engine("fill_mesh_holes", relief_depth_fill_params_default(), table, count, kw,
                       {progress, cancel}, v, faces, colours, nb::none(), nb::none(),
                       depth_fill_mesh_call, relief_depth_fill_report_free);
}

// ------------------------------------------------------------------ files

nb::tuple read_mesh(const std::string &path)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_error err{};
    relief_mesh *m = nullptr;
    relief_status s = without_gil(scope, &err, [&] {
        return relief_mesh_read(path.c_str(), &m, nullptr, &err);
    });
    nb::object arrays = s == RELIEF_OK ? nb::object(mesh_arrays(m)) : nb::none();
    relief_mesh_destroy(m);
    return nb::make_tuple(int(s), std::string(err.message), arrays);
}

nb::tuple write_mesh(const std::string &path, carray<const double> v, nb::object faces,
                     nb::object colours, nb::object labels, bool ascii)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_error err{};
    relief_mesh *m = nullptr;
    relief_status s = make_mesh(v, faces, colours, nb::none(), labels, &m, &err);
    relief_write_options o{ascii ? 1 : 0};
    if (s == RELIEF_OK)
        s = without_gil(scope, &err, [&] { return relief_mesh_write(m, path.c_str(), &o, &err); });
    relief_mesh_destroy(m);
    return nb::make_tuple(int(s), std::string(err.message));
}

// (status, message, samples as H x W x C uint8 or uint16)
nb::tuple read_image(const std::string &path)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_error err{};
    relief_image img;
    std::memset(&img, 0, sizeof img);
    relief_status s = without_gil(scope, &err, [&] {
        return relief_image_read(path.c_str(), 0, &img, &err);
    });
    nb::object arr = nb::none();
    if (s == RELIEF_OK) {
        const size_t h = size_t(img.height), row = size_t(img.width) * size_t(img.channels);
        const size_t shape[3] = {h, size_t(img.width), size_t(img.channels)};
        if (img.bit_depth == 8) {
            auto *buf = new uint8_t[h * row + 1];
            std::memcpy(buf, img.data, h * row);
            nb::capsule own(buf, [](void *q) noexcept { delete[] static_cast<uint8_t *>(q); });
            arr = nb::cast(carray<uint8_t>(buf, 3, shape, own));
        } else {
            auto *buf = new uint16_t[h * row + 1];
            std::memcpy(buf, img.data, h * row * 2);
            nb::capsule own(buf, [](void *q) noexcept { delete[] static_cast<uint16_t *>(q); });
            arr = nb::cast(carray<uint16_t>(buf, 3, shape, own));
        }
    }
    relief_image_free(&img);
    return nb::make_tuple(int(s), std::string(err.message), arr);
}

// image: H x W x C (C 1 to 4) uint8 or uint16; PNG or JPEG by the extension.
nb::tuple write_image(const std::string &path,
                      nb::ndarray<nb::ro, nb::c_contig, nb::device::cpu> image)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_error err{};
    relief_image img{int(image.shape(1)), int(image.shape(0)), int(image.shape(2)),
                     int(image.dtype().bits), 0, const_cast<void *>(image.data())};
    relief_status s = without_gil(scope, &err, [&] {
        return relief_image_write(&img, path.c_str(), &err);
    });
    return nb::make_tuple(int(s), std::string(err.message));
}

// z: H x W float32 (NaN missing), as a PFM or a 16-bit PNG (png_scale).
nb::tuple write_depth(const std::string &path, carray<const float> z, const std::string &format,
                      double png_scale)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_error err{};
    relief_depth_image f;
    std::memset(&f, 0, sizeof f);
    f.width = int(z.shape(1)), f.height = int(z.shape(0)), f.z = const_cast<float *>(z.data());
    const relief_depth_format fmt = format == "png16" ? RELIEF_DEPTH_PNG16 : RELIEF_DEPTH_PFM;
    relief_status s = without_gil(scope, &err, [&] {
        return relief_depth_write(&f, path.c_str(), fmt, png_scale, &err);
    });
    return nb::make_tuple(int(s), std::string(err.message));
}

// (status, message, z as H x W float32, NaN where missing, rgb as (H W) x 3
// uint8 or None, xyz as (H W) x 3 float32 or None, the format's name);
// encoding as relief_depth_encoding_name spells it (checked by the Python
// side).
nb::tuple read_depth(const std::string &path, double png_scale, const std::string &encoding)
{
    call_scope scope; // first: it outlives everything the call holds
    relief_error err{};
    relief_depth_image f;
    std::memset(&f, 0, sizeof f);
    int enc = 0;
    while (enc <= RELIEF_DEPTH_ENCODING_SUN &&
           encoding != relief_depth_encoding_name(relief_depth_encoding(enc)))
        ++enc;
    relief_status s = without_gil(scope, &err, [&] {
        return relief_depth_read_as(path.c_str(), relief_depth_encoding(enc), png_scale, 0, &f,
                                    &err);
    });
    nb::object z = nb::none(), rgb = nb::none(), xyz = nb::none(), format = nb::none();
    if (s == RELIEF_OK) {
        const size_t shape[2] = {size_t(f.height), size_t(f.width)}, n = shape[0] * shape[1];
        auto *buf = new float[shape[0] * shape[1] + 1];
        std::memcpy(buf, f.z, shape[0] * shape[1] * sizeof(float));
        nb::capsule own(buf, [](void *q) noexcept { delete[] static_cast<float *>(q); });
        z = nb::cast(carray<float>(buf, 2, shape, own));
        rgb = new_array(f.rgb, n, 3), xyz = new_array(f.xyz, n, 3);
        format = nb::str(relief_depth_format_name(f.format));
    }
    relief_depth_image_free(&f);
    return nb::make_tuple(int(s), std::string(err.message), z, rgb, xyz, format);
}

nb::tuple devices()
{
    relief_device_info info[64];
    size_t n = 0;
    relief_error err{};
    relief_status s = relief_devices(info, 64, &n, &err);
    nb::list out;
    for (size_t i = 0; s == RELIEF_OK && i < n && i < 64; ++i) {
        nb::dict d;
        d["index"] = info[i].index;
        d["platform"] = std::string(info[i].platform);
        d["name"] = std::string(info[i].name);
        d["type"] = std::string(info[i].type);
        d["version"] = std::string(info[i].version);
        d["compute_units"] = info[i].compute_units;
        d["global_mem_bytes"] = info[i].global_mem_bytes;
        out.append(d);
    }
    return nb::make_tuple(int(s), std::string(err.message), out);
}

// Every parameter of an engine: name -> (value form, help).
nb::dict param_table(const std::string &engine)
{
    size_t count = 0;
    const relief_param *t = engine == "image_fill"        ? relief_image_fill_param_table(&count)
                            : engine == "depth_fill" || engine == "fill_mesh_holes"
                                ? relief_depth_fill_param_table(&count)
                            : engine == "complete_mesh"   ? relief_complete_param_table(&count)
                            : engine == "complete_points" ? relief_complete_points_param_table(&count)
                            : engine == "find_occluders" || engine == "remove_occluders"
                                ? relief_occluder_param_table(&count)
                                : nullptr;
    nb::dict d;
    for (size_t i = 0; t && i < count; ++i)
        d[t[i].name] = nb::make_tuple(std::string(t[i].value ? t[i].value : ""),
                                      std::string(t[i].help ? t[i].help : ""));
    return d;
}

} // namespace

NB_MODULE(_relief, m)
{
    m.doc() = "librelief's engines; use the package relief, which checks the arguments";
    m.def("version", [] { return std::string(relief_version()); });
    m.def("status_name", [](int s) { return std::string(relief_status_name(relief_status(s))); });
    m.def("image_fill", &image_fill, "image"_a, "mask"_a, "params"_a, "progress"_a.none(),
          "cancel"_a.none());
    m.def("depth_fill", &depth_fill, "z"_a, "mask"_a.none(), "colour"_a.none(), "params"_a,
          "progress"_a.none(), "cancel"_a.none());
    m.def("image_fill_check_memory", &image_fill_check_memory, "height"_a, "width"_a,
          "channels"_a, "params"_a);
    m.def("depth_fill_check_memory", &depth_fill_check_memory, "height"_a, "width"_a,
          "params"_a);
    m.def("complete_mesh", &complete_mesh, "vertices"_a, "faces"_a.none(), "colours"_a.none(),
          "params"_a, "progress"_a.none(), "cancel"_a.none());
    m.def("fill_mesh_holes", &fill_mesh_holes, "vertices"_a, "faces"_a.none(),
          "colours"_a.none(), "params"_a, "progress"_a.none(), "cancel"_a.none());
    m.def("complete_points", &complete_points, "points"_a, "faces"_a.none(), "colours"_a.none(),
          "normals"_a.none(), "labels"_a.none(), "params"_a, "progress"_a.none(),
          "cancel"_a.none());
    m.def("find_occluders", &find_occluders, "z"_a, "xyz"_a.none(), "rgb"_a, "colours"_a,
          "poses"_a, "params"_a);
    m.def("remove_occluders", &remove_occluders, "z"_a, "xyz"_a.none(), "rgb"_a,
          "mask"_a.none(), "colours"_a, "poses"_a, "params"_a, "colour_params"_a,
          "depth_params"_a, "cancel"_a.none());
    m.def("cancel_all", [] { g_cancel_generation.fetch_add(1); });
    m.def("at_exit", &at_exit, "timeout"_a);
    m.def("after_fork_in_child", &after_fork_in_child);
    m.def("read_mesh", &read_mesh);
    m.def("write_mesh", &write_mesh, "path"_a, "vertices"_a, "faces"_a.none(), "colours"_a.none(),
          "labels"_a.none(), "ascii"_a);
    m.def("read_image", &read_image);
    m.def("read_depth", &read_depth);
    m.def("write_image", &write_image);
    m.def("write_depth", &write_depth);
    m.def("devices", &devices);
    m.def("param_table", &param_table);
}
