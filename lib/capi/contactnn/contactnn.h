/* contactnn.h: the C interface of contactnn's run-time local search (lib/search, SPEC 2, 4, 6 and 8), for
 * finite-element codes written in C, Fortran (module contactnn, contactnn.f90, binds this header) or any
 * language that calls C.
 *
 * A search is one method on one surface kind, with its options and (network methods) a network file,
 * fixed at creation; it then finds, for batches of slave-node / master-segment pairs given in world
 * coordinates, the local coordinates of the closest point on the segment, the gap, a status and the Newton
 * steps taken. The computation is contactnn::search::LocalSearch's (search/local_search.hpp): blocks of
 * queries vectorised across queries, blocks in parallel with OpenMP, every query's result independent of
 * the batch it is in.
 *
 * Conventions:
 *  - Every function that can fail returns a CONTACTNN_* return code (CONTACTNN_SUCCESS = 0) and no C++
 *    exception ever leaves it; on failure contactnn_last_error() holds a message naming the argument or file,
 *    the expected and the actual value.
 *  - Arrays are C row-major: query i's values are contiguous. In Fortran column-major terms raw is
 *    raw(15, n) or raw(27, n) and param is param(2, n), so Fortran arrays pass unchanged.
 *  - Units: coordinates in any consistent length unit (the gap is in the same unit); local coordinates
 *    (xi, eta) in [-1, 1]^2 for the bilinear facet, (u, v) in [0, 1]^2 for the Gregory patch (SPEC 1).
 *  - Thread safety: any number of threads may run one search at the same time (a run only reads it);
 *    destroy it only when no run is under way.
 *  - Handles carry a check value, written by contactnn_search_create and cleared by contactnn_search_destroy:
 *    a call given a handle that was destroyed, or a pointer to something that is not a handle, answers
 *    CONTACTNN_ERROR_INVALID_ARGUMENT ("not a live handle") instead of crashing, and destroying a handle
 *    twice frees nothing the second time. This catches the common mistakes, not every one: using freed
 *    memory is undefined behaviour, the memory of a destroyed handle may already hold a new handle (the call
 *    then uses that one), and a pointer into unmapped memory still crashes. Creating searches is serialised
 * inside the library (the network file is read with HDF5, which Debian builds without thread safety); a
 * program that uses HDF5 itself must not do so while a search is being created.
 *
 * Sample use (error handling shortened):
 *   contactnn_search* s = NULL;
 *   if (contactnn_search_create(&s, CONTACTNN_SURFACE_BILINEAR, "network+newton:2", "bilinear-8.h5", NULL))
 *     fprintf(stderr, "contactnn: %s\n", contactnn_last_error());
 *   contactnn_search_run(s, n, raw, param, gap, status, NULL);
 *   contactnn_search_destroy(s);
 *
 * Link: CMake `find_package(contactnn REQUIRED)` and `target_link_libraries(app PRIVATE contactnn::c)`;
 * otherwise `-I<prefix>/include -L<prefix>/lib -lcontactnn_c`.
 */
#ifndef CONTACTNN_CONTACTNN_H
#define CONTACTNN_CONTACTNN_H

#include <stddef.h>

#if defined(__GNUC__)
#define CONTACTNN_API __attribute__((visibility("default")))
#else
#define CONTACTNN_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Return codes. 1 to 5 are the contactnn tools' exit codes for the same kinds of failure. */
enum contactnn_return_code {
  CONTACTNN_SUCCESS = 0,
  CONTACTNN_ERROR_INTERNAL = 1,         /* a bug in contactnn: please report the message */
  CONTACTNN_ERROR_INVALID_ARGUMENT = 2, /* a NULL pointer, unknown surface or method, option out of range */
  CONTACTNN_ERROR_FORMAT = 3,           /* the network file is not a contactnn network of a known schema */
  CONTACTNN_ERROR_IO = 4,               /* the network file cannot be opened or read */
  CONTACTNN_ERROR_NUMERICAL = 5,        /* a non-finite value where a finite one is required */
  CONTACTNN_ERROR_OUT_OF_MEMORY = 6
};

/* Per-query statuses: the values of contactnn::Status (SPEC 2), never renumbered. */
enum contactnn_status {
  CONTACTNN_STATUS_OK = 0,             /* converged (or estimated), inside the parameter domain */
  CONTACTNN_STATUS_OUTSIDE = 1,        /* converged, outside the domain; coordinates still reported */
  CONTACTNN_STATUS_NO_CONVERGENCE = 2, /* Newton did not converge or a safeguarded step stalled */
  CONTACTNN_STATUS_DEGENERATE = 3,     /* the segment or its Jacobian is unusable (collapsed, no frame) */
  CONTACTNN_STATUS_INVALID = 4,        /* a non-finite input */
  CONTACTNN_STATUS_OUT_OF_DOMAIN = 5,  /* network methods: outside the network's training domain */
  CONTACTNN_STATUS_NO_SEGMENT = 6      /* SPEC 7: no segment for the slave node (never returned by a run) */
};

/* Surface kinds: 0 and 1 are the values of contactnn::SurfaceKind (a 4-node segment,
 * search/local_search.hpp); 2 to 4 the other faces of SPEC 9, contactnn::search::FaceKind + 2
 * (search/face_search.hpp). A face's raw row is its nodes' x, y, z in SPEC 9's order (corners, then the
 * mid-side nodes of edges 1-2, 2-3, ...), then S's. */
enum contactnn_surface {
  CONTACTNN_SURFACE_BILINEAR = 0, /* 4-node bilinear facet: raw rows of 15 values */
  CONTACTNN_SURFACE_GREGORY = 1,  /* Gregory patch from nodes and node normals: raw rows of 27 values */
  CONTACTNN_SURFACE_TRI3 = 2, /* flat 3-node triangle, (r, s): raw rows of 12 values; closed_form is exact */
  CONTACTNN_SURFACE_TRI6 = 3, /* 6-node quadratic triangle, (r, s): raw rows of 21 values */
  CONTACTNN_SURFACE_QUAD8 = 4 /* 8-node serendipity quad, (xi, eta): raw rows of 27 values */
};

/* The most OpenMP threads a run uses (the contactnn tools' --threads limit too). */
#define CONTACTNN_MAX_THREADS 1024

/* The tolerances and limits of a search: contactnn::search::SearchOptions plus the thread count. Fill it
 * with contactnn_options_init (the library's defaults) and change the fields you need. Each field has the
 * range written beside it (reals finite: NaN and infinities are outside every range); contactnn_search_create
 * and contactnn_search_create_from_plan refuse a value outside it with CONTACTNN_ERROR_INVALID_ARGUMENT and a
 * message naming the field and its range (contactnn_last_error). Within the ranges one query does a bounded
 * amount of work: at most max_iterations Newton steps ("newton") or K ("newton:K", hybrids; K <= 1000), each
 * step halved at most max_halvings times. */
typedef struct contactnn_options {
  int threads;        /* OpenMP threads per run, at most CONTACTNN_MAX_THREADS; <= 0: OpenMP's default
                         (OMP_NUM_THREADS), capped at CONTACTNN_MAX_THREADS. Default 0 */
  int check_domain;   /* network methods: nonzero tests each query against the network's training domain
                         (status out_of_domain); a query on a tie then averages the network over its
                         canonical forms in the domain, else over all of them. Default 1 */
  int max_iterations; /* "newton" (to convergence): iteration limit, 1 to 1000. Default 50 */
  int max_halvings;   /* hybrids: halvings of a step that does not reduce |S - P|, 0 to 60. Default 3 */
  double tol_param; /* "newton": converged when the step (max norm, parameter units) is at most this, 0 to 1.
                       Default 1e-10 */
  double domain_margin;       /* ok versus outside: slack of the parameter domain, parameter units, 0 to 1.
                                 Default 1e-10 */
  double gregory_box_margin;  /* hybrids, Gregory: iterates stay in the domain enlarged by this many domain
                                 widths, 0 to 1. Default 0: the segment itself, [0, 1]^2 */
  double bilinear_box_margin; /* hybrids, bilinear: the same for the facet, 0 to 1. Default 0.25 */
  double max_step_widths;     /* hybrids: longest Newton step in domain widths (max norm), > 0 and <= 1.
                                 Default 0.5 */
  size_t min_parallel_count;  /* below this many queries a run stays on the calling thread. Default 512 */
} contactnn_options;

/* Opaque handle of a search. */
typedef struct contactnn_search contactnn_search;

/* The library's version as "MAJOR.MINOR.PATCH"; the numbers are also written to major, minor and patch
 * where those are not NULL. Never fails. */
CONTACTNN_API const char* contactnn_version(int* major, int* minor, int* patch);

/* The message of the most recent call that failed on the calling thread ("" when none has); calls that
 * succeed leave it unchanged. Valid until the next failing call on the same thread. */
CONTACTNN_API const char* contactnn_last_error(void);

/* Records `message` as this thread's last error and returns `code`: for language bindings that check
 * arguments themselves (the Fortran module does), so that every error reads the same way. */
CONTACTNN_API int contactnn_set_last_error(int code, const char* message);

/* The CSV spelling of a status ("ok", "outside", "no_convergence", "degenerate", "invalid",
 * "out_of_domain", "no_segment"), or "unknown" for any other value. Never fails. */
CONTACTNN_API const char* contactnn_status_name(int status);

/* Values per query in raw for a surface: 15 (bilinear), 27 (Gregory), 12 (tri3), 21 (tri6), 27 (quad8), 0 for
 * any other value. */
CONTACTNN_API int contactnn_raw_columns(int surface);

/* Writes the default options (those of search/search_options.hpp, threads 0) to *options.
 * Returns CONTACTNN_ERROR_INVALID_ARGUMENT when options is NULL. */
CONTACTNN_API int contactnn_options_init(contactnn_options* options);

/* Creates a search.
 *   search        where the handle is written (NULL on failure)
 *   surface       CONTACTNN_SURFACE_BILINEAR, _GREGORY, or a face type of SPEC 9: _TRI3, _TRI6, _QUAD8 (the
 *                 methods of search/face_search.hpp: every method below but four_triangles; no network on
 *                 tri3, whose closed_form is exact; closed_form on tri6 and quad8 is the corner facet's)
 *   method        "network", "newton:K", "newton", "closed_form", "network+newton:K",
 *                 "closed_form+newton:K", "start+newton:K" (K from 0 to 1000; search/method.hpp describes
 *                 each) or, bilinear only, "four_triangles" (after OpenRadioss's type 7 contact: the nearest
 *                 point of the four triangles about the segment's centroid, no iteration; another surface
 *                 than the bilinear facet)
 *   network_file  a network file of train-net (HDF5; for tri6 and quad8 a face network file of scene-study
 *                 --face), or NULL / "" for the methods without a network. It is
 *                 read once, here; a network file given to a method without a network is still read and
 *                 must be of the search's surface.
 *   options       NULL for the defaults
 * Errors: INVALID_ARGUMENT (NULL search or method, an unknown surface or method, a network method without
 * network_file, a network of the other surface or of the other kind: train-net's network for tri6 or quad8, a
 * face network for bilinear or Gregory; an option out of range), IO (network_file cannot be opened or read:
 * missing, no permission, a directory), FORMAT (it is not a contactnn network, or is damaged). Messages quote
 * a method or file name of more than 40 bytes by its first 40 and its length; a network_file longer than 4096
 * bytes (PATH_MAX) is INVALID_ARGUMENT. */
CONTACTNN_API int contactnn_search_create(contactnn_search** search, int surface, const char* method,
                                          const char* network_file, const contactnn_options* options);

/* Frees a search (NULL is allowed and does nothing). A search destroyed already, or a pointer that is not a
 * search, is left alone and recorded as this thread's last error (see "Handles" above for the limits). */
CONTACTNN_API void contactnn_search_destroy(contactnn_search* search);

/* Runs the search on `count` queries (count = 0 does nothing and succeeds).
 *   raw         count x 15 (bilinear) or count x 27 (Gregory), row-major, in SPEC 6's column order:
 *               ax ay az bx by bz cx cy cz dx dy dz sx sy sz (segment nodes A, B, C, D counter-clockwise seen
 *               from the side the normal points to, then the slave node S), then for Gregory the node
 *               normals nax nay naz nbx nby nbz ncx ncy ncz ndx ndy ndz (any positive length)
 *   param       count x 2, out: (xi, eta) or (u, v) in the caller's node order. Finite for every status:
 *               the estimate, or the last iterate, or the domain centre (invalid; network methods:
 *               degenerate). In and out for the method start+newton:K: each query's start on input (e.g.
 *               the pair's local coordinates at the previous time step; not finite: status invalid)
 *   gap         count, out, optional (NULL: not computed): g = n.(S - P) at the reported point, n the unit
 *               normal of the caller's parametrisation, g < 0 penetration; 0 for invalid and degenerate
 *               (four_triangles: +-|S - P| with the sign of (S - P).(C - A)x(D - B))
 *   status      count, out: CONTACTNN_STATUS_* per query (search/local_search.hpp lists them by method)
 *   iterations  count, out, optional (NULL: not written): Newton steps taken (0 for network, closed_form,
 *               four_triangles)
 * The geometry is computed in double whatever the call's precision, a network in its own precision.
 * Allocates count bytes of scratch per call (the statuses before their widening to int).
 * Errors: INVALID_ARGUMENT (NULL search, a search destroyed already or not a search, NULL raw, param or
 * status with count > 0, or count so large that count x 27 values overflow), OUT_OF_MEMORY. A failed run may
 * have written part of the outputs. */
CONTACTNN_API int contactnn_search_run(const contactnn_search* search, size_t count, const double* raw,
                                       double* param, double* gap, int* status, int* iterations);
/* The same in single precision (inputs and outputs float; a gap beyond the float range, possible for inputs
 * near FLT_MAX, is written as +-FLT_MAX). */
CONTACTNN_API int contactnn_search_run_float(const contactnn_search* search, size_t count, const float* raw,
                                             float* param, float* gap, int* status, int* iterations);

/* The surface (CONTACTNN_SURFACE_*) a search was created for, or -1 for NULL, a search destroyed already or
 * a pointer that is not a search. Never fails. */
CONTACTNN_API int contactnn_search_surface(const contactnn_search* search);

/* Creates a search from a scene plan: the DIR/plan.toml that scene-study writes for one contact pair of a
 * deck (SPEC 7; the format is lib/io/plan_file.hpp's), in place of a surface, a method and a network file:
 * the plan's surface, its method and, where the method uses one, its network file (a path relative to the
 * plan's own directory, or absolute). The plan is read once, here. search     where the handle is written
 * (NULL on failure) plan_file  the plan's path options    NULL for the defaults The plan decides the surface:
 * contactnn_search_surface tells it (raw rows of 15 or 27 values), and contactnn_search_method the method it
 * chose. Errors: INVALID_ARGUMENT (NULL search or plan_file, an empty plan_file or one longer than 4096
 * bytes, an option out of range), IO (the plan or its network file cannot be opened or read: missing, no
 * permission, a directory), FORMAT (the plan is not a valid plan: the message names the file, the line and
 * the key; or its network file is not a contactnn network, or one of the other surface). */
CONTACTNN_API int contactnn_search_create_from_plan(contactnn_search** search, const char* plan_file,
                                                    const contactnn_options* options);

/* The method of a search as its name ("network+newton:1", "closed_form", ...: search/method.hpp's names), or
 * "" for NULL, a search destroyed already or a pointer that is not a search. Valid until the next call of
 * this function on the same thread. Never fails. */
CONTACTNN_API const char* contactnn_search_method(const contactnn_search* search);

/* ---------------------------------------------------------------------------------------------------------
 * The contact search handle (contactnn::contact::ContactSearch, contact/contact_search.hpp; issue 38): the
 * whole surface search of SPEC 9 for an FE code. Created once from the master faces and the slave points;
 * then, at every increment, given the node coordinates, it answers for every slave point the closest point of
 * the master surface (a face's interior, an edge or a vertex), its signed gap and the unit normal, into
 * arrays the caller owns. Tracking (the previous increment's candidate faces and points) lives inside the
 * handle: the first update is a fresh search, the later ones give a fresh search's answers at less cost.
 *
 *   faces         n_faces face types (CONTACTNN_FACE_*) and their node ids, concatenated in connectivity (4,
 * 8, 3 or 6 ids per face, by its type): the corners counter-clockwise seen from outside (the side a positive
 * gap lies on), then a quadratic face's mid-side nodes of the edges 1-2, 2-3, ... (SPEC 9) nodes n_nodes
 * nodes in the coordinate array; a node id names node (id - id_base) (id_base 0 in C, 1 in Fortran), or,
 * where node_ids is not NULL, the node whose id node_ids holds (an FE code's global ids; distinct) slave
 * points  n_slaves slave node ids (slave_node_ids), or, with slave_node_ids NULL, n_slaves free points
 *                 (integration points) whose coordinates every update passes
 * Face i is reported as face i (from 0). SPEC 9's tie rule (equal distances to 1e-12 of the face size) takes
 * the lower face index.
 *
 * The face-interior method (options.method, .network_file, .plan_file; all NULL by default): without one the
 * search is exact (lib/projection's reference on every candidate face). With a method of
 * contactnn_search_create ("closed_form+newton:2", "newton:4", "network+newton:1" with its network file; not
 * start+newton:K) or a scene plan (scene-study's DIR/plan.toml: its method and network file), that method
 * answers each candidate face first (contact/narrow_phase.hpp): its point is taken where it lies inside the
 * face and within the capture distance, the exact closest point otherwise (edges, vertices, tri3 faces, pairs
 * it refuses), so no slave point the exact search finds is lost and only face-interior points carry the
 * method's error. The files are read once, at creation.
 *
 * Per slave point i, an update writes (optional arrays may be NULL):
 *   status[i]     CONTACTNN_STATUS_OK: found; CONTACTNN_STATUS_NO_SEGMENT: no face within the capture
 * distance face[i]       the face index (from 0), -1 when none location[i]   CONTACTNN_LOCATION_FACE, _EDGE
 * or _VERTEX: where the point lies on its face; -1 when none param[2i..]   local coordinates in the face's
 * own node order: (xi, eta) in [-1, 1]^2 (quad4 bilinear, quad8), (u, v) in [0, 1]^2 (quad4 Gregory), (r, s)
 * of a triangle point[3i..]   the closest point P gap[i]        the signed distance |S - P|, negative where S
 * penetrates normal[3i..]  unit normal: the face's outward normal at P for a point inside a face; (S - P) /
 * gap at an edge or a vertex (S = P + gap n); the face's normal at P where S lies on the surface A slave
 * point without a face gets 0 in param, point, gap and normal. Bad input (a face naming a node that does not
 * exist, a non-finite coordinate, a count that does not match the handle's) returns its code and message and
 * writes NOTHING to the caller's arrays; the handle stays usable. Thread safety: one update of a handle at a
 * time (an update changes its tracking state); separate handles are independent. Handles carry a check value
 * as contactnn_search's do (see "Handles" above).
 *
 * Sample use (error handling shortened):
 *   contactnn_contact* c = NULL;
 *   contactnn_contact_create(&c, n_faces, types, conn, n_nodes, NULL, 0, n_slaves, slave_ids, NULL);
 *   for (int inc = 0; inc < n_inc; ++inc) {
 *     ... coords[3 * node] = x, y, z of each node ...
 *     contactnn_contact_update(c, n_nodes, coords, n_slaves, NULL, status, face, location, param, point, gap,
 * normal);
 *   }
 *   contactnn_contact_destroy(c);
 */

/* Face types: the values of contactnn::mesh::FaceType. */
enum contactnn_face_type {
  CONTACTNN_FACE_QUAD4 = 0, /* 4 corners: a bilinear facet, or a Gregory patch (options.quad4_surface) */
  CONTACTNN_FACE_QUAD8 = 1, /* 8 nodes: the serendipity quadrilateral through them */
  CONTACTNN_FACE_TRI3 = 2,  /* 3 corners: a flat triangle */
  CONTACTNN_FACE_TRI6 = 3   /* 6 nodes: the quadratic triangle through them */
};

/* Where the closest point lies on its face: the values of contactnn::Location. */
enum contactnn_location {
  CONTACTNN_LOCATION_FACE = 0,
  CONTACTNN_LOCATION_EDGE = 1,
  CONTACTNN_LOCATION_VERTEX = 2
};

/* The options of a contact search. Fill it with contactnn_contact_options_init and change what you need. */
typedef struct contactnn_contact_options {
  double capture_distance; /* a face counts when its closest point lies within this distance (world units);
                              <= 0: one largest face size of the state searched. Default 0 */
  int quad4_surface;       /* CONTACTNN_SURFACE_BILINEAR or CONTACTNN_SURFACE_GREGORY (node normals of Eq 26
                              over the quad4 and quad8 faces). Default bilinear */
  int threads;        /* OpenMP threads of an update, at most CONTACTNN_MAX_THREADS; <= 0: OpenMP's default.
                         The answers are the same bits for any count. Default 0 */
  int tracking;       /* nonzero: reuse the previous increment's candidates and points (the same answers);
                         0: every update a fresh search. Default 1 */
  const char* method; /* the face-interior method (see above): a method name of contactnn_search_create
                         but start+newton:K; NULL or "": the exact search. Default NULL */
  const char* network_file; /* the network file of a network method (train-net's, of quad4_surface's kind);
                               NULL or "" for the other methods. Default NULL */
  const char* plan_file;    /* a scene plan (DIR/plan.toml, SPEC 7) in place of method and network_file: its
                               method and network file (relative to the plan's directory). Its surface must be
                               quad4_surface. NULL or "": none. Default NULL */
} contactnn_contact_options;

/* Opaque handle of a contact search. */
typedef struct contactnn_contact contactnn_contact;

/* Writes the default options to *options. INVALID_ARGUMENT when options is NULL. */
CONTACTNN_API int contactnn_contact_options_init(contactnn_contact_options* options);

/* Creates a contact search (the arguments above; options NULL for the defaults). The arrays and the options'
 * strings are read here and not kept. Errors: INVALID_ARGUMENT (NULL contact, faces, connectivity or, with
 * n_slaves > 0, nothing to say what the slave points are; n_faces or n_nodes 0; a face type that is none of
 * CONTACTNN_FACE_*; a face naming a node that does not exist or a node twice; repeated node_ids; a slave node
 * that does not exist; an option out of range; options.method not a method name, start+newton:K, a network
 * method without network_file, a network_file without a method; a network or a plan of the other surface than
 * quad4_surface; plan_file with method or network_file; a path longer than 4096 bytes), IO (network_file,
 * plan_file or the plan's network file cannot be opened or read: the message names the file), FORMAT (the
 * plan is not a valid plan: the message names the file, the line and the key; a network file that is not a
 * contactnn network), OUT_OF_MEMORY. The message names the face, its node and the id, or the option and the
 * file. On failure *contact is NULL: nothing is created. */
CONTACTNN_API int contactnn_contact_create(contactnn_contact** contact, size_t n_faces, const int* face_types,
                                           const int* connectivity, size_t n_nodes, const int* node_ids,
                                           int id_base, size_t n_slaves, const int* slave_node_ids,
                                           const contactnn_contact_options* options);

/* Frees a contact search (NULL does nothing; a handle destroyed already is left alone and recorded as the
 * last error). */
CONTACTNN_API void contactnn_contact_destroy(contactnn_contact* contact);

/* One increment: coords holds n_nodes x 3 values (x, y, z of each node, in the coordinate array's order),
 * slave_points n_slaves x 3 for a search of free points (NULL for slave nodes). n_nodes and n_slaves must be
 * the handle's. Writes the arrays above (status and face required, the rest optional). Errors:
 * INVALID_ARGUMENT (NULL or dead handle, a count that is not the handle's, a NULL required array), NUMERICAL
 * (a non-finite coordinate of a node of a face, of a slave node or of a free point: the message names it),
 * OUT_OF_MEMORY; then nothing is written. */
CONTACTNN_API int contactnn_contact_update(contactnn_contact* contact, size_t n_nodes, const double* coords,
                                           size_t n_slaves, const double* slave_points, int* status,
                                           int* face, int* location, double* param, double* point,
                                           double* gap, double* normal);

/* The number of slave points of a contact search, or -1 for NULL or a handle that is not live. Never fails.
 */
CONTACTNN_API long contactnn_contact_slave_count(const contactnn_contact* contact);

#ifdef __cplusplus
}
#endif

#endif /* CONTACTNN_CONTACTNN_H */
