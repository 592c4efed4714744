/* Siconos plugins for the rocking block's two corners (models/rocking-block.toml), written by
 * hand from the model file's constraints
 *
 *   left  = y - b sin(theta) - c cos(theta)
 *   right = y + b sin(theta) - c cos(theta)
 *
 * with q = (x, y, theta). peer.py checks these against the file's formulas before it uses them,
 * and compiles this file into a shared library (cc -shared -fPIC) that Siconos loads through
 * LagrangianScleronomousR("LIB:left_h", "LIB:left_G0", "LIB:left_dotG0").
 *
 * Why C and not a Python subclass: Siconos's event-driven scheme takes the term dG0/dt q_dot
 * of the acceleration-level problem from LagrangianScleronomousR::computedotjacqhXqdot, which
 * calls the plugin of the base class directly, so a Python override of computeDotJachq never
 * reaches it (the run then fails at the first impact, see README.md).
 *
 * The parameters are not written here: they come from the model file through the dynamical
 * system's z vector, z = (b, c).
 *
 * Signatures (Siconos 4.4, PluginTypes.hpp): h and G0 are FPtr3
 *   (sizeQ, q, sizeY, out, sizeZ, z); dotG0 is FPtr2 (sizeQ, q, sizeQdot, qdot, out, sizeZ, z).
 * G0 and dotG0 are 1 x 3 matrices (one row per contact).
 */
#include <math.h>

/* s = -1 for the left corner, +1 for the right one. */
static void corner_h(double s, const double *q, double *y, const double *z)
{
  const double b = z[0], c = z[1], th = q[2];
  y[0] = q[1] + s * b * sin(th) - c * cos(th);
}

static void corner_G0(double s, const double *q, double *G, const double *z)
{
  const double b = z[0], c = z[1], th = q[2];
  G[0] = 0.0;
  G[1] = 1.0;
  G[2] = s * b * cos(th) + c * sin(th);
}

static void corner_dotG0(double s, const double *q, const double *v, double *dG, const double *z)
{
  const double b = z[0], c = z[1], th = q[2];
  dG[0] = 0.0;
  dG[1] = 0.0;
  dG[2] = (-s * b * sin(th) + c * cos(th)) * v[2];
}

void left_h(unsigned int nq, double *q, unsigned int ny, double *y, unsigned int nz, double *z)
{
  (void)nq; (void)ny; (void)nz;
  corner_h(-1.0, q, y, z);
}

void left_G0(unsigned int nq, double *q, unsigned int ny, double *G, unsigned int nz, double *z)
{
  (void)nq; (void)ny; (void)nz;
  corner_G0(-1.0, q, G, z);
}

void left_dotG0(unsigned int nq, double *q, unsigned int nv, double *v, double *dG,
                unsigned int nz, double *z)
{
  (void)nq; (void)nv; (void)nz;
  corner_dotG0(-1.0, q, v, dG, z);
}

void right_h(unsigned int nq, double *q, unsigned int ny, double *y, unsigned int nz, double *z)
{
  (void)nq; (void)ny; (void)nz;
  corner_h(1.0, q, y, z);
}

void right_G0(unsigned int nq, double *q, unsigned int ny, double *G, unsigned int nz, double *z)
{
  (void)nq; (void)ny; (void)nz;
  corner_G0(1.0, q, G, z);
}

void right_dotG0(unsigned int nq, double *q, unsigned int nv, double *v, double *dG,
                 unsigned int nz, double *z)
{
  (void)nq; (void)nv; (void)nz;
  corner_dotG0(1.0, q, v, dG, z);
}
