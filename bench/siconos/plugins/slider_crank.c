/* Siconos plugins for the slider-crank with a translational clearance joint
 * (models/siconos/slider-crank-d1minus*.toml, the ports of SliderCrank/SliderCrankD1MinusLinear*.cpp),
 * written from the model file: with q = (q1, q2, q3) the crank's, the rod's and the slider's
 * angles, K = (m2/2 + m3) l1 l2 and s = sin(q2 - q1), c = cos(q2 - q1), the file's Lagrangian
 * gives
 *
 *   M = [[J1 + (m1/4 + m2 + m3) l1^2, K c, 0], [K c, J2 + (m2/4 + m3) l2^2, 0], [0, 0, J3]]
 *   FGyr = (-K s q2'^2, K s q1'^2, 0)
 *   FInt = g ((m1/2 + m2 + m3) l1 cos q1, (m2/2 + m3) l2 cos q2, 0)    (gravity)
 *
 * and the four corners of the slider against the guide, with y = l1 sin q1 + l2 sin q2,
 *
 *   g1 = d/2 - (y - a sin q3 + b cos q3)    g2 = d/2 - (y + a sin q3 + b cos q3)
 *   g3 = d/2 + (y - a sin q3 - b cos q3)    g4 = d/2 + (y + a sin q3 - b cos q3)
 *
 * with their gradients W and dW/dt. The parameters are compiled in from the file (-DL1= -DL2=
 * -DA= -DB= -DD= -DM1= -DM2= -DM3= -DJ1= -DJ2= -DJ3= -DG=). Signatures as in Siconos 4.4
 * (PluginTypes.hpp); matrices column-major.
 */
#include <math.h>

#define KC ((0.5 * M2 + M3) * L1 * L2)

void mass(unsigned int n, double *q, double *M, unsigned int nz, double *z)
{
  (void)n; (void)nz; (void)z;
  const double c = cos(q[1] - q[0]);
  M[0] = J1 + (0.25 * M1 + M2 + M3) * L1 * L1;
  M[1] = KC * c;
  M[2] = 0.0;
  M[3] = KC * c;
  M[4] = J2 + (0.25 * M2 + M3) * L2 * L2;
  M[5] = 0.0;
  M[6] = 0.0;
  M[7] = 0.0;
  M[8] = J3;
}

void FGyr(unsigned int n, double *q, double *v, double *f, unsigned int nz, double *z)
{
  (void)n; (void)nz; (void)z;
  const double s = sin(q[1] - q[0]);
  f[0] = -KC * s * v[1] * v[1];
  f[1] = KC * s * v[0] * v[0];
  f[2] = 0.0;
}

void jacobianFGyrq(unsigned int n, double *q, double *v, double *J, unsigned int nz, double *z)
{
  (void)n; (void)nz; (void)z;
  const double c = cos(q[1] - q[0]);
  for (int i = 0; i < 9; i++) J[i] = 0.0;
  J[0] = KC * c * v[1] * v[1];   /* d f0/d q1 */
  J[1] = -KC * c * v[0] * v[0];  /* d f1/d q1 */
  J[3] = -KC * c * v[1] * v[1];  /* d f0/d q2 */
  J[4] = KC * c * v[0] * v[0];   /* d f1/d q2 */
}

void jacobianFGyrqDot(unsigned int n, double *q, double *v, double *J, unsigned int nz,
                      double *z)
{
  (void)n; (void)nz; (void)z;
  const double s = sin(q[1] - q[0]);
  for (int i = 0; i < 9; i++) J[i] = 0.0;
  J[1] = 2.0 * KC * s * v[0];    /* d f1/d q1' */
  J[3] = -2.0 * KC * s * v[1];   /* d f0/d q2' */
}

void FInt(double t, unsigned int n, double *q, double *v, double *f, unsigned int nz, double *z)
{
  (void)t; (void)n; (void)v; (void)nz; (void)z;
  f[0] = G * (0.5 * M1 + M2 + M3) * L1 * cos(q[0]);
  f[1] = G * (0.5 * M2 + M3) * L2 * cos(q[1]);
  f[2] = 0.0;
}

void jacobianFIntq(double t, unsigned int n, double *q, double *v, double *J, unsigned int nz,
                   double *z)
{
  (void)t; (void)n; (void)v; (void)nz; (void)z;
  for (int i = 0; i < 9; i++) J[i] = 0.0;
  J[0] = -G * (0.5 * M1 + M2 + M3) * L1 * sin(q[0]);
  J[4] = -G * (0.5 * M2 + M3) * L2 * sin(q[1]);
}

void jacobianFIntqDot(double t, unsigned int n, double *q, double *v, double *J,
                      unsigned int nz, double *z)
{
  (void)t; (void)n; (void)q; (void)v; (void)nz; (void)z;
  for (int i = 0; i < 9; i++) J[i] = 0.0;
}

/* g = d/2 + sg (l1 sin q1 + l2 sin q2) + sa a sin q3 - b cos q3 */
static void gap(double sg, double sa, const double *q, double *y)
{
  y[0] = 0.5 * D + sg * (L1 * sin(q[0]) + L2 * sin(q[1])) + sa * A * sin(q[2]) - B * cos(q[2]);
}

static void grad(double sg, double sa, const double *q, double *W)
{
  W[0] = sg * L1 * cos(q[0]);
  W[1] = sg * L2 * cos(q[1]);
  W[2] = sa * A * cos(q[2]) + B * sin(q[2]);
}

static void grad_dot(double sg, double sa, const double *q, const double *v, double *W)
{
  W[0] = -sg * L1 * sin(q[0]) * v[0];
  W[1] = -sg * L2 * sin(q[1]) * v[1];
  W[2] = (-sa * A * sin(q[2]) + B * cos(q[2])) * v[2];
}

#define CORNER(k, sg, sa)                                                                    \
  void g##k(unsigned int n, double *q, unsigned int ny, double *y, unsigned int nz, double *z) \
  {                                                                                          \
    (void)n; (void)ny; (void)nz; (void)z;                                                    \
    gap(sg, sa, q, y);                                                                       \
  }                                                                                          \
  void W##k(unsigned int n, double *q, unsigned int ny, double *W, unsigned int nz, double *z) \
  {                                                                                          \
    (void)n; (void)ny; (void)nz; (void)z;                                                    \
    grad(sg, sa, q, W);                                                                      \
  }                                                                                          \
  void W##k##dot(unsigned int n, double *q, unsigned int nv, double *v, double *W,           \
                 unsigned int nz, double *z)                                                 \
  {                                                                                          \
    (void)n; (void)nv; (void)nz; (void)z;                                                    \
    grad_dot(sg, sa, q, v, W);                                                               \
  }

CORNER(1, -1.0, 1.0)
CORNER(2, -1.0, -1.0)
CORNER(3, 1.0, -1.0)
CORNER(4, 1.0, 1.0)
