"""Numbers in text whatever the program's locale (issue 60). After
locale.setlocale to a comma-decimal locale, where the program's own
formatting writes a half as "0,5", relief still reads a PFM's scale and an
ascii PCD's points, takes a float parameter, writes its reports' JSON with
'.' (json.loads reads them), quotes a value in a message as it was given,
and reads and writes an ascii PLY's fractional coordinates; the program's
locale is left as it was. (ctest's test_python_comma runs the whole suite
in that locale too.)
"""
import locale
import struct

import numpy as np
import pytest

import relief

PCD = ("# .PCD v0.7 - Point Cloud Data file format\n"
       "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
       "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
       "0.5 0.25 1.5\n-0.75 0.125 2.5\nnan nan nan\n1.25 -0.5 3.75\n")

PLY = ("ply\nformat ascii 1.0\nelement vertex 4\n"
       "property float x\nproperty float y\nproperty float z\n"
       "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1.5 0 0.25\n1.5 2.5 0.5\n0 2.5 0.75\n3 0 1 2\n3 0 2 3\n")
PLY_VERTICES = [[0, 0, 0], [1.5, 0, 0.25], [1.5, 2.5, 0.5], [0, 2.5, 0.75]]


def stripes():
    """A 48 x 48 grey image of diagonal stripes and a 5 x 5 hole in it."""
    y, x = np.mgrid[:48, :48]
    img = np.where((x + y) % 8 < 4, 40, 200).astype(np.uint8)
    mask = np.zeros(img.shape, np.uint8)
    mask[20:25, 20:25] = 1
    return img, mask


def test_the_locale_is_comma_decimal(comma_locale):
    assert locale.format_string("%.1f", 0.5) == "0,5"


def test_read_depth(comma_locale, tmp_path):
    pfm = tmp_path / "half.pfm"  # rows bottom to top, little-endian (scale -1.0)
    pfm.write_bytes(b"Pf\n3 2\n-1.0\n" + struct.pack("<6f", 3.5, 4.5, 5.5, 0.5, 1.5, 2.5))
    assert relief.read_depth(pfm).tolist() == [[0.5, 1.5, 2.5], [3.5, 4.5, 5.5]]
    pcd = tmp_path / "half.pcd"
    pcd.write_text(PCD)
    z = relief.read_depth(pcd)
    assert z[0, 0] == 1.5 and z[0, 1] == 2.5 and np.isnan(z[1, 0]) and z[1, 1] == 3.75
    relief.write_depth(tmp_path / "again.pfm", z)
    assert np.array_equal(relief.read_depth(tmp_path / "again.pfm"), z, equal_nan=True)


def test_float_parameters_and_reports(comma_locale):
    img, mask = stripes()
    _, rep = relief.image_fill(img, mask, window=9, backend="scalar", max_hole_fraction=0.25,
                               return_report=True)
    assert rep["parameters"]["max_hole_fraction"] == 0.25
    z = (1.5 + 0.01 * np.arange(64, dtype=np.float32))[None, :].repeat(64, 0)
    z[20:30, 20:30] = np.nan
    out, rep = relief.depth_fill(z, backend="scalar", sigma=1.5, epsilon=0.25,
                                 return_report=True)
    assert np.isfinite(out[20:30, 20:30]).all() and isinstance(rep, dict)


def test_a_message_quotes_the_value(comma_locale):
    img, mask = stripes()
    with pytest.raises(relief.ReliefError, match=r"max_hole_fraction 1\.5 "):
        relief.image_fill(img, mask, window=9, max_hole_fraction=1.5)


@pytest.mark.parametrize("name", ["again.ply", "again.off", "again.obj"])
def test_mesh_text(comma_locale, tmp_path, name):
    (tmp_path / "quad.ply").write_text(PLY)
    m = relief.read_mesh(tmp_path / "quad.ply")
    assert m.vertices.tolist() == PLY_VERTICES
    relief.write_mesh(tmp_path / name, m.vertices, m.faces, ascii=True)
    text = (tmp_path / name).read_text()
    assert "1.5" in text and "0.25" in text and "1,5" not in text and "0,25" not in text
    assert relief.read_mesh(tmp_path / name).vertices.tolist() == PLY_VERTICES


def test_the_program_keeps_its_locale(comma_locale):
    relief.parameters("image_fill")
    relief.image_fill(*stripes(), window=9, backend="scalar", max_hole_fraction=0.25)
    assert locale.setlocale(locale.LC_NUMERIC) == comma_locale
    assert locale.format_string("%.2f", 0.25) == "0,25"
