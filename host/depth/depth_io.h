/* Depth frames as depth cameras and stereo benchmarks write them (issue
 * 20, paper 003): an organised PCD (PCL's format: x y z [rgb] per pixel,
 * DATA ascii, binary or binary_compressed, the last through liblzf) and a
 * PFM (Portable Float Map, Middlebury's disparities: "Pf" grey or "PF"
 * colour, the scale's sign giving the byte order, rows bottom to top).
 * Decoded from memory (the fuzz harness's entry) or from a file. */
#ifndef RELIEF_HOST_DEPTH_DEPTH_IO_H
#define RELIEF_HOST_DEPTH_DEPTH_IO_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "base/output.h"

/* The public depth image (relief/depth.h) is the frame every reader and
 * writer here takes; its format says how it was read and is written. */
typedef relief_depth_image relief_depth_frame;
typedef relief_depth_format relief_depth_kind;

void relief_depth_frame_free(relief_depth_frame *f);

/* Decode `n` bytes of an organised PCD. The fields x, y and z (type F,
 * size 4 or 8, count 1) are required, rgb or rgba (size 4) is kept when
 * present, any other field is skipped. `max_pixels` (0: no limit) refuses
 * larger frames before they are allocated (RELIEF_E_NOMEM). Errors name
 * `name` and the header line or the byte: RELIEF_E_PARSE (malformed or
 * truncated), RELIEF_E_FORMAT (an unorganised cloud, HEIGHT 1; a field
 * layout not supported), RELIEF_E_RANGE (a side over the maximum). */
relief_status relief_pcd_decode(const uint8_t *data, size_t n, const char *name,
                                uint64_t max_pixels, relief_depth_frame *out,
                                relief_error *err);

/* The same for a point cloud, organised or not (an unorganised one,
 * HEIGHT 1, comes back as a WIDTH x 1 frame): the entry of the point-set
 * reader (issue 21). `max_points` as max_pixels. */
relief_status relief_pcd_decode_cloud(const uint8_t *data, size_t n, const char *name,
                                      uint64_t max_points, relief_depth_frame *out,
                                      relief_error *err);

/* Read a PCD file as relief_pcd_decode_cloud decodes it; RELIEF_E_IO
 * naming the path when it cannot be read. */
relief_status relief_pcd_read_cloud(const char *path, uint64_t max_points,
                                    relief_depth_frame *out, relief_error *err);

/* The finite points of a frame with xyz (a PCD's), as a point set with
 * colour when f has rgb, in the frame's order; *dropped (may be NULL) gets
 * the non-finite ones' count. RELIEF_E_PARSE naming `name` when no point is
 * finite, RELIEF_E_RANGE when f has no xyz; RELIEF_E_NOMEM. */
relief_status relief_depth_frame_points(const relief_depth_frame *f, const char *name,
                                        relief_mesh **out, size_t *dropped, relief_error *err);

/* Decode `n` bytes of a PFM: "Pf" (one channel) or "PF" (three; the
 * first is kept), width, height, scale (negative: little endian). Same
 * errors. */
relief_status relief_pfm_decode(const uint8_t *data, size_t n, const char *name,
                                uint64_t max_pixels, relief_depth_frame *out,
                                relief_error *err);

/* Decode `n` bytes as a PCD or a PFM, told by the first bytes (as
 * relief_depth_frame_read does); RELIEF_E_FORMAT when they are neither. */
relief_status relief_depth_frame_decode(const uint8_t *data, size_t n, const char *name,
                                  uint64_t max_pixels, relief_depth_frame *out,
                                  relief_error *err);

/* Read a depth file by its first bytes: PCD ("# .PCD" or "VERSION") or
 * PFM ("Pf", "PF"). RELIEF_E_IO naming the path when it cannot be read;
 * RELIEF_E_FORMAT when it is neither. */
relief_status relief_depth_frame_read(const char *path, uint64_t max_pixels,
                                relief_depth_frame *out, relief_error *err);

/* Write `f` into the sink s (base/output.h) as `kind`: a PFM ("Pf", little endian,
 * rows bottom to top) of z, NaN written as +inf (Middlebury's unknown); or
 * an organised PCD v0.7 with fields x y z (F 4) and rgb (F 4, PCL's packed
 * colour) when f->rgb is set, DATA ascii, binary or binary_compressed
 * (LZF, field by field). A PCD needs f->xyz. Failures name s->path. */
relief_status relief_depth_frame_write_to(relief_sink *s, const relief_depth_frame *f,
                                          relief_depth_kind kind, relief_error *err);

/* The same to `path`, whole or not at all. */
relief_status relief_depth_frame_write(const char *path, const relief_depth_frame *f,
                                       relief_depth_kind kind, relief_error *err);

/* relief_depth_write (relief/depth.h) into the sink s, the same checks and
 * bytes, for a caller that stages the file itself. */
relief_status relief_depth_write_to(relief_sink *s, const relief_depth_image *f,
                                    relief_depth_format format, double png_scale,
                                    relief_error *err);

#endif
