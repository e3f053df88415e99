/* GIMP 2.10 plug-in: Filters > Enhance > Heal Selection (relief), procedure
 * plug-in-relief-heal-selection. Fills the active drawable's selection with
 * relief_image_fill's default method (multi-scale patch voting, issue 62)
 * sampled from the rest of the drawable, in one undo step, with GIMP's
 * progress bar. The window argument is paper 004's (--method jain), kept
 * so that scripts calling the procedure keep working; the default method
 * does not read it.
 *
 * Arguments: run-mode, image, drawable, window (odd pixels, 3..1025; 17),
 * seed (0..2^31 - 1; 1). Interactive runs ask for window and seed in a
 * dialog and keep the last values; RUN-WITH-LAST-VALS reuses them.
 *
 * The drawable is read whole (the fill samples from everything outside the
 * selection), as 8-bit samples for an 8-bit image and 16-bit for any other
 * precision, grey or RGB with or without alpha; the selection's non-zero
 * pixels are the hole. The result goes through the shadow buffer, which
 * GIMP merges under the selection: pixels outside it are not touched, a
 * feathered edge blends. Written in C against libgimp2.0-dev because
 * Debian's GIMP 2.10 has no Python plug-ins. */
#include <libgimp/gimp.h>
#include <libgimp/gimpui.h>
#include <string.h>

#include "relief/relief.h"

#define PROC "plug-in-relief-heal-selection"
#define BINARY "relief-heal-selection"

typedef struct heal_values {
    gint32 window, seed;
} heal_values;

static void query(void);
static void run(const gchar *name, gint nparams, const GimpParam *param, gint *nreturn_vals,
                GimpParam **return_vals);

const GimpPlugInInfo PLUG_IN_INFO = {NULL, NULL, query, run};

MAIN()

static void query(void)
{
    static const GimpParamDef args[] = {
        {GIMP_PDB_INT32, "run-mode", "The run mode { RUN-INTERACTIVE (0), RUN-NONINTERACTIVE (1) }"},
        {GIMP_PDB_IMAGE, "image", "Input image"},
        {GIMP_PDB_DRAWABLE, "drawable", "The drawable whose selected pixels are filled"},
        {GIMP_PDB_INT32, "window", "Paper 004's starting window, odd pixels (3..1025; 17); "
                                   "the default patch voting does not read it"},
        {GIMP_PDB_INT32, "seed", "Seed of the random start and search (1)"},
    };
    gimp_install_procedure(PROC, "Fill the selection with texture sampled from the rest of the "
                                 "drawable (relief)",
                           "Fills the selected pixels of the drawable by relief's image fill: "
                           "a 1-D pass where a gap's ends agree and are smooth, then "
                           "multi-scale patch voting (Wexler et al. 2007 with PatchMatch's "
                           "search), coarse to fine. Pixels outside the selection are not "
                           "changed.",
                           "the relief authors", "the relief authors (BSD-3-Clause)", "2026",
                           "_Heal Selection (relief)...", "RGB*, GRAY*", GIMP_PLUGIN,
                           G_N_ELEMENTS(args), 0, args, NULL);
    gimp_plugin_menu_register(PROC, "<Image>/Filters/Enhance");
}

/* ------------------------------------------------------------- the dialog */

static gboolean ask(heal_values *v)
{
    GtkWidget *dialog, *grid;
    GtkAdjustment *window, *seed;
    gboolean ok;
    gimp_ui_init(BINARY, FALSE);
    dialog = gimp_dialog_new("Heal Selection (relief)", BINARY, NULL, 0, gimp_standard_help_func,
                             PROC, "_Cancel", GTK_RESPONSE_CANCEL, "_OK", GTK_RESPONSE_OK, NULL);
    grid = gtk_table_new(2, 3, FALSE);
    gtk_table_set_row_spacings(GTK_TABLE(grid), 6);
    gtk_table_set_col_spacings(GTK_TABLE(grid), 6);
    gtk_container_set_border_width(GTK_CONTAINER(grid), 12);
    gtk_box_pack_start(GTK_BOX(gtk_dialog_get_content_area(GTK_DIALOG(dialog))), grid, TRUE,
                       TRUE, 0);
    window = GTK_ADJUSTMENT(gimp_scale_entry_new(GTK_TABLE(grid), 0, 0, "_Window:", 200, 6,
                                                 v->window, 3, 129, 2, 16, 0, FALSE, 3, 1025,
                                                 "Starting window, odd pixels", NULL));
    seed = GTK_ADJUSTMENT(gimp_scale_entry_new(GTK_TABLE(grid), 0, 1, "_Seed:", 200, 6, v->seed,
                                               0, 1000, 1, 10, 0, FALSE, 0, G_MAXINT32,
                                               "Seed of the fallback's random choice", NULL));
    gtk_widget_show_all(dialog);
    ok = gimp_dialog_run(GIMP_DIALOG(dialog)) == GTK_RESPONSE_OK;
    if (ok) {
        v->window = (gint32)gtk_adjustment_get_value(window) | 1;
        v->seed = (gint32)gtk_adjustment_get_value(seed);
    }
    gtk_widget_destroy(dialog);
    return ok;
}

/* ---------------------------------------------------------------- the fill */

static int progress(void *ctx, double fraction)
{
    (void)ctx;
    gimp_progress_update(fraction);
    return 0;
}

/* The drawable's babl format at `bits` per sample. */
static const Babl *format_of(gint32 drawable, int bits, int *channels)
{
    const gboolean alpha = gimp_drawable_has_alpha(drawable);
    char name[32];
    *channels = (gimp_drawable_is_rgb(drawable) ? 3 : 1) + (alpha ? 1 : 0);
    g_snprintf(name, sizeof name, "%s%s u%d", gimp_drawable_is_rgb(drawable) ? "R'G'B'" : "Y'",
               alpha ? "A" : "", bits);
    return babl_format(name);
}

/* Fill the selected pixels of `drawable`; NULL on success, else a message
 * (owned by the caller). */
static gchar *heal(gint32 image, gint32 drawable, const heal_values *v)
{
    const int w = gimp_drawable_width(drawable), h = gimp_drawable_height(drawable);
    const GimpPrecision prec = gimp_image_get_precision(image);
    const int bits = prec == GIMP_PRECISION_U8_LINEAR || prec == GIMP_PRECISION_U8_GAMMA ? 8 : 16;
    int channels, ox, oy, x, y, sw, sh;
    const Babl *fmt = format_of(drawable, bits, &channels);
    GeglBuffer *buf, *sel, *shadow;
    guchar *pixels, *mask;
    relief_image img, m;
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_error err = {0};
    relief_status st;

    if (gimp_selection_is_empty(image) ||
        !gimp_drawable_mask_intersect(drawable, &x, &y, &sw, &sh))
        return g_strdup("Heal Selection (relief): nothing is selected on this layer; select "
                        "the pixels to fill first");
    pixels = g_try_malloc((gsize)w * h * channels * (bits / 8));
    mask = g_try_malloc((gsize)w * h);
    if (!pixels || !mask) {
        g_free(pixels), g_free(mask);
        return g_strdup_printf("Heal Selection (relief): not enough memory for a %d x %d "
                               "layer", w, h);
    }
    buf = gimp_drawable_get_buffer(drawable);
    gegl_buffer_get(buf, GEGL_RECTANGLE(0, 0, w, h), 1.0, fmt, pixels, GEGL_AUTO_ROWSTRIDE,
                    GEGL_ABYSS_NONE);
    gimp_drawable_offsets(drawable, &ox, &oy);
    sel = gimp_drawable_get_buffer(gimp_image_get_selection(image));
    gegl_buffer_get(sel, GEGL_RECTANGLE(ox, oy, w, h), 1.0, babl_format("Y u8"), mask,
                    GEGL_AUTO_ROWSTRIDE, GEGL_ABYSS_NONE);
    g_object_unref(sel);

    img = (relief_image){w, h, channels, bits, 0, pixels};
    m = (relief_image){w, h, 1, 8, 0, mask};
    p.window = v->window;
    p.seed = (uint32_t)v->seed;
    p.run.progress = progress;
    gimp_progress_init("Heal Selection (relief)");
    st = relief_image_fill(&img, &m, &p, NULL, &err);
    if (st == RELIEF_OK) {
        shadow = gimp_drawable_get_shadow_buffer(drawable);
        gegl_buffer_set(shadow, GEGL_RECTANGLE(0, 0, w, h), 0, fmt, pixels, GEGL_AUTO_ROWSTRIDE);
        gegl_buffer_flush(shadow);
        g_object_unref(shadow);
        gimp_drawable_merge_shadow(drawable, TRUE); /* one undo step */
        gimp_drawable_update(drawable, x, y, sw, sh);
    }
    gimp_progress_end();
    g_object_unref(buf);
    g_free(pixels), g_free(mask);
    return st == RELIEF_OK ? NULL : g_strdup_printf("Heal Selection (relief): %s", err.message);
}

static void run(const gchar *name, gint nparams, const GimpParam *param, gint *nreturn_vals,
                GimpParam **return_vals)
{
    static GimpParam values[2];
    const GimpRunMode mode = (GimpRunMode)param[0].data.d_int32;
    heal_values v = {17, 1};
    gchar *msg = NULL;
    (void)name;
    *nreturn_vals = 1;
    *return_vals = values;
    values[0].type = GIMP_PDB_STATUS;
    values[0].data.d_status = GIMP_PDB_SUCCESS;
    gegl_init(NULL, NULL);
    gimp_get_data(PROC, &v);
    if (mode == GIMP_RUN_NONINTERACTIVE) {
        if (nparams != 5) {
            values[0].data.d_status = GIMP_PDB_CALLING_ERROR;
            return;
        }
        v.window = param[3].data.d_int32, v.seed = param[4].data.d_int32;
    } else if (mode == GIMP_RUN_INTERACTIVE && !ask(&v)) {
        values[0].data.d_status = GIMP_PDB_CANCEL;
        return;
    }
    gimp_image_undo_group_start(param[1].data.d_image);
    msg = heal(param[1].data.d_image, param[2].data.d_drawable, &v);
    gimp_image_undo_group_end(param[1].data.d_image);
    if (msg) {
        static gchar text[RELIEF_ERROR_MESSAGE_MAX + 64];
        g_strlcpy(text, msg, sizeof text);
        g_free(msg);
        values[0].data.d_status = GIMP_PDB_EXECUTION_ERROR;
        values[1].type = GIMP_PDB_STRING;
        values[1].data.d_string = text;
        *nreturn_vals = 2;
        return;
    }
    if (mode != GIMP_RUN_NONINTERACTIVE)
        gimp_displays_flush();
    if (mode == GIMP_RUN_INTERACTIVE)
        gimp_set_data(PROC, &v, sizeof v);
}
