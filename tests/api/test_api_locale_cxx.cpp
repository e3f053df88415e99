// A C++ program's global locale (issue 60): after
// std::locale::global(std::locale("de_DE.UTF-8")), every C++ stream made
// afterwards, OpenMesh's own included, reads "1.5" as 15 and writes "1,5".
// relief still reads an ascii PLY's fractional coordinates, writes PLY, OFF,
// OBJ and STL with '.', and refuses a text OFF it would misread, saying why.
// Through the C API and the shared library, as a C++ user calls it.
//   tests/comma_locale.sh LOCALE_DIR test_api_locale_cxx
// (RELIEF_TEST_LOCALE names the locale; without it the test is skipped.)
#include <cstdio>
#include <cstdlib>
#include <locale>
#include <string>

#include "api_test.h"

static const char ply[] =
    "ply\nformat ascii 1.0\nelement vertex 4\n"
    "property float x\nproperty float y\nproperty float z\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1.5 0 0.25\n1.5 2.5 0.5\n0 2.5 0.75\n3 0 1 2\n3 0 2 3\n";
static const char off[] = "OFF\n4 2 0\n0 0 0\n1.5 0 0.25\n1.5 2.5 0.5\n0 2.5 0.75\n"
                          "3 0 1 2\n3 0 2 3\n";

static std::string dir;

static std::string put(const char *name, const char *text)
{
    std::string path = dir + "/" + name;
    FILE *f = std::fopen(path.c_str(), "wb");
    if (f) {
        std::fputs(text, f);
        std::fclose(f);
    }
    return path;
}

static std::string slurp(const std::string &path)
{
    std::string text;
    FILE *f = std::fopen(path.c_str(), "rb");
    char buf[4096];
    size_t n;
    while (f && (n = std::fread(buf, 1, sizeof buf, f)) > 0)
        text.append(buf, n);
    if (f)
        std::fclose(f);
    return text;
}

static bool quad(relief_mesh *m)
{
    static const double want[12] = {0, 0, 0, 1.5, 0, 0.25, 1.5, 2.5, 0.5, 0, 2.5, 0.75};
    const double *p = relief_mesh_positions(m);
    if (relief_mesh_vertex_count(m) != 4)
        return false;
    for (int i = 0; i < 12; ++i)
        if (p[i] != want[i])
            return false;
    return true;
}

int main()
{
    const char *name = std::getenv("RELIEF_TEST_LOCALE");
    char tmp[] = "/tmp/relief-api-locale-cxx-XXXXXX";
    relief_error err{};
    relief_mesh *m = nullptr;
    if (!name || !name[0]) {
        std::printf("RELIEF_TEST_LOCALE unset: run me through tests/comma_locale.sh; skipped\n");
        return 77;
    }
    if (!mkdtemp(tmp))
        return 2;
    dir = tmp;
    std::locale::global(std::locale(name)); // C's setlocale(LC_ALL) too
    CHECK(std::use_facet<std::numpunct<char>>(std::locale()).decimal_point() == ',',
          "%s is not comma-decimal", name);
    CHECK_STATUS(relief_mesh_read(put("quad.ply", ply).c_str(), &m, nullptr, &err), RELIEF_OK,
                 err, NULL);
    CHECK(m && quad(m), "the ascii PLY's coordinates");
    for (const char *ext : {"ply", "off", "obj", "stl"}) {
        std::string path = dir + "/again." + ext, text;
        relief_write_options o = {1};
        if (!m)
            break;
        CHECK_STATUS(relief_mesh_write(m, path.c_str(), &o, &err), RELIEF_OK, err, NULL);
        text = slurp(path);
        CHECK(text.find("1.5") != std::string::npos && text.find("1,5") == std::string::npos &&
                  text.find("0,25") == std::string::npos,
              "%s written with '.': %s", ext, text.c_str());
    }
    relief_mesh_destroy(m);
    m = nullptr;
    CHECK_STATUS(relief_mesh_read((dir + "/again.ply").c_str(), &m, nullptr, &err), RELIEF_OK,
                 err, NULL);
    CHECK(m && quad(m), "the written PLY read back");
    relief_mesh_destroy(m);
    m = nullptr;
    CHECK_STATUS(relief_mesh_read(put("quad.off", off).c_str(), &m, nullptr, &err),
                 RELIEF_E_USAGE, err, "C++ global locale");
    relief_mesh_destroy(m);
    std::system(("rm -rf '" + dir + "'").c_str());
    API_TEST_END();
}
