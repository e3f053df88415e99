/* The names of the public enumerations, from the lists that define them
 * (the public headers' X-macro lists), so that a name is written once. */
#include "relief/relief.h"

#define RELIEF_X_CASE(code, name) \
    case code: return name;

/* NAME_FN(function, type, list): "unknown" for a value not in the list. */
#define NAME_FN(fn, type, list)      \
    const char *fn(type value)       \
    {                                \
        switch (value) {             \
            list(RELIEF_X_CASE)      \
        }                            \
        return "unknown";            \
    }

NAME_FN(relief_backend_name, relief_backend, RELIEF_BACKEND_LIST)
NAME_FN(relief_base_name, relief_base, RELIEF_BASE_LIST)
NAME_FN(relief_fill_region_name, relief_fill_region, RELIEF_FILL_REGION_LIST)
NAME_FN(relief_frames_name, relief_frames, RELIEF_FRAMES_LIST)
NAME_FN(relief_oversample_scheme_name, relief_oversample_scheme,
        RELIEF_OVERSAMPLE_SCHEME_LIST)
NAME_FN(relief_search_name, relief_search_mode, RELIEF_SEARCH_LIST)
NAME_FN(relief_depth_format_name, relief_depth_format, RELIEF_DEPTH_FORMAT_LIST)
NAME_FN(relief_depth_encoding_name, relief_depth_encoding, RELIEF_DEPTH_ENCODING_LIST)
NAME_FN(relief_depth_variant_name, relief_depth_variant, RELIEF_DEPTH_VARIANT_LIST)
NAME_FN(relief_depth_order_name, relief_depth_order, RELIEF_DEPTH_ORDER_LIST)
NAME_FN(relief_membrane_name, relief_membrane, RELIEF_MEMBRANE_LIST)
NAME_FN(relief_depth_edges_name, relief_depth_edges, RELIEF_DEPTH_EDGES_LIST)
NAME_FN(relief_depth_values_name, relief_depth_values, RELIEF_DEPTH_VALUES_LIST)
NAME_FN(relief_points_what_name, relief_points_what, RELIEF_POINTS_WHAT_LIST)
NAME_FN(relief_grid_search_name, relief_grid_search, RELIEF_GRID_SEARCH_LIST)
NAME_FN(relief_background_name, relief_background, RELIEF_BACKGROUND_LIST)
NAME_FN(relief_seeding_name, relief_seeding, RELIEF_SEEDING_LIST)
NAME_FN(relief_noise_model_name, relief_noise_model, RELIEF_NOISE_MODEL_LIST)
NAME_FN(relief_image_fill_method_name, relief_image_fill_method,
        RELIEF_IMAGE_FILL_METHOD_LIST)

NAME_FN(relief_fit_model_name, relief_fit_model, RELIEF_FIT_MODEL_LIST)
