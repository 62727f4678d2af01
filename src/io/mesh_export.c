/*
** Mesh export through Assimp's C API (see mesh_export.h).
*/
#include "mesh_export.h"

#include <assimp/cexport.h>
#include <assimp/cimport.h>
#include <assimp/scene.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "../geom/csg.h"
#include "../geom/shape2d.h"
#include "tempfile.h"

/* Assimp's id of the format for path: binary STL for .stl; NULL for
** anything else (Assimp's other exporters want materials and names a
** solid does not have). */
static const char *format_for(const char *path) {
  const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
  if (!dot || (slash && dot < slash)) return NULL;
  return !strcasecmp(dot + 1, "stl") ? "stlb" : NULL;
}

/* One object's closed mesh in world space, appended to the aiMesh. */
static void add_object(struct aiMesh *am, const Mesh *m, Mat4 to_world, unsigned *nv, unsigned *nf) {
  for (int v = 0; v < m->nverts; v++) {
    Vec3 p = m4_point(to_world, m->pos[v]);
    am->mVertices[*nv + (unsigned)v] = (struct aiVector3D){(ai_real)p.x, (ai_real)p.y, (ai_real)p.z};
  }
  for (int t = 0; t < m->ntris; t++) {
    struct aiFace *f = &am->mFaces[*nf + (unsigned)t];
    f->mNumIndices = 3;
    f->mIndices = malloc(3 * sizeof *f->mIndices);
    if (!f->mIndices) sumi_fatal("out of memory");
    for (int k = 0; k < 3; k++) f->mIndices[k] = *nv + (unsigned)m->tri[t][k];
  }
  *nv += (unsigned)m->nverts;
  *nf += (unsigned)m->ntris;
}

/* The objects' meshes (NULL for those left out), with a warning each. */
static Mesh **object_meshes(const Scene *s, unsigned *nv, unsigned *nf, int *ok) {
  Mesh **ms = xcalloc((size_t)s->nobjects + 1, sizeof *ms);
  *nv = *nf = 0;
  *ok = 1;
  for (int i = 0; i < s->nobjects && *ok; i++) {
    const SceneObject *o = &s->objects[i];
    const SceneGeometry *g = o->geometry;
    if (!g || shape2d_is_empty(g)) continue;
    if (shape2d_is_2d(g)) {
      diag_warning(o->loc, "export writes solids: this 2D shape is left out (linear_extrude it)");
      continue;
    }
    char err[256];
    SceneGeometry one = *g;
    if (g->kind == GEOM_PATCHES && o->tess_kind == TESS_UNIFORM) one.tess_n = o->tess_n;
    ms[i] = csg_operand_mesh(&one, err, sizeof err);
    if (!ms[i]) {
      diag_error(o->loc, "%s", err);
      *ok = 0;
      break;
    }
    *nv += (unsigned)ms[i]->nverts;
    *nf += (unsigned)ms[i]->ntris;
  }
  if (s->norigami) diag_warning(s->origami[0].loc, "export writes solids: origami is left out");
  return ms;
}

static void free_scene(struct aiScene *as) {
  struct aiMesh *am = as->mMeshes ? as->mMeshes[0] : NULL;
  if (am) {
    for (unsigned f = 0; f < am->mNumFaces; f++) free(am->mFaces[f].mIndices);
    free(am->mFaces);
    free(am->mVertices);
    free(am);
  }
  free(as->mMeshes);
  if (as->mMaterials) free(as->mMaterials[0]);
  free(as->mMaterials);
  if (as->mRootNode) free(as->mRootNode->mMeshes);
  free(as->mRootNode);
}

int mesh_export_scene(const Scene *s, const char *path) {
  const char *fmt = format_for(path);
  if (!fmt) {
    fprintf(stderr, "sumi: cannot export '%s': export writes binary STL, to a .stl file\n",
            path);
    return 0;
  }
  unsigned nv, nf;
  int ok;
  Mesh **ms = object_meshes(s, &nv, &nf, &ok);
  struct aiScene as;
  memset(&as, 0, sizeof as);
  struct aiNode *root = xcalloc(1, sizeof *root);
  struct aiMesh *am = xcalloc(1, sizeof *am);
  strcpy(root->mName.data, "sumi");
  root->mName.length = 4;
  root->mTransformation.a1 = root->mTransformation.b2 = root->mTransformation.c3 = root->mTransformation.d4 = 1;
  root->mNumMeshes = 1;
  root->mMeshes = xcalloc(1, sizeof *root->mMeshes);
  as.mRootNode = root;
  as.mNumMeshes = 1;
  as.mMeshes = xcalloc(1, sizeof *as.mMeshes);
  as.mMeshes[0] = am;
  /* Assimp's exporters want a material to point at: one without properties */
  struct aiMaterial *mat = xcalloc(1, sizeof *mat);
  as.mNumMaterials = 1;
  as.mMaterials = xcalloc(1, sizeof *as.mMaterials);
  as.mMaterials[0] = mat;
  am->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  am->mVertices = xcalloc((size_t)nv + 1, sizeof *am->mVertices);
  am->mFaces = xcalloc((size_t)nf + 1, sizeof *am->mFaces);
  unsigned v0 = 0, f0 = 0;
  for (int i = 0; ok && i < s->nobjects; i++)
    if (ms[i]) add_object(am, ms[i], s->objects[i].transform, &v0, &f0);
  am->mNumVertices = v0;
  am->mNumFaces = f0;
  for (int i = 0; i < s->nobjects; i++)
    if (ms[i]) mesh_destroy(ms[i]);
  free(ms);
  if (ok) {
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp-%ld", path, (long)getpid());
    int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      fprintf(stderr, "sumi: cannot write '%s': %s\n", path, strerror(errno));
      ok = 0;
    } else {
      close(fd);
      tempfile_add(tmp);
      if (aiExportScene(&as, fmt, tmp, 0) != aiReturn_SUCCESS) {
        fprintf(stderr, "sumi: cannot write '%s': %s\n", path, aiGetErrorString());
        ok = 0;
      } else if (rename(tmp, path) != 0) {
        fprintf(stderr, "sumi: cannot write '%s': %s\n", path, strerror(errno));
        ok = 0;
      }
      if (ok) tempfile_forget(tmp);
      else tempfile_discard(tmp);
    }
  }
  free_scene(&as);
  return ok;
}
