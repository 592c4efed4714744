/* Siconos plugins for the double pendulum against a wall (models/siconos/double-pendulum-ts.toml,
 * the port of Pendulum/DoublePendulumTS.cpp), written from the model file's Lagrangian
 *
 *   L = 1/2 (m1 + m2) l1^2 th1'^2 + 1/2 m2 l2^2 th2'^2 + m2 l1 l2 cos(th1 - th2) th1' th2'
 *       + (m1 + m2) g l1 cos(th1) + m2 g l2 cos(th2)
 *
 * as Siconos's LagrangianDS wants it, M(q) q'' + FGyr(q, v) + FInt(q) = 0, and its two
 * constraints h0 = l1 sin(th1) (the first mass against the wall x = 0) and h1 = l1 sin(th1) +
 * l2 sin(th2) (the second). The parameters are compiled in from the file: -DM1= -DM2= -DL1= -DL2=
 * -DG= (suite.py checks every function against the file's formulas before a run).
 *
 * Signatures (Siconos 4.4, PluginTypes.hpp): mass (n, q, M, nz, z); FGyr and its Jacobians
 * (n, q, v, out, nz, z); FInt and its Jacobians (t, n, q, v, out, nz, z); h and G0 (n, q, ny,
 * out, nz, z). Matrices are column-major: out[i + n j] = d out_i / d x_j.
 */
#include <math.h>

void mass(unsigned int n, double *q, double *M, unsigned int nz, double *z)
{
  (void)n; (void)nz; (void)z;
  const double c = cos(q[0] - q[1]);
  M[0] = (M1 + M2) * L1 * L1;
  M[1] = M2 * L1 * L2 * c;
  M[2] = M2 * L1 * L2 * c;
  M[3] = M2 * L2 * L2;
}

void FGyr(unsigned int n, double *q, double *v, double *f, unsigned int nz, double *z)
{
  (void)n; (void)nz; (void)z;
  const double k = M2 * L1 * L2, s = sin(q[0] - q[1]);
  f[0] = k * s * v[1] * v[1];
  f[1] = -k * s * v[0] * v[0];
}

void jacobianFGyrq(unsigned int n, double *q, double *v, double *J, unsigned int nz, double *z)
{
  (void)n; (void)nz; (void)z;
  const double k = M2 * L1 * L2, c = cos(q[0] - q[1]);
  J[0] = k * c * v[1] * v[1];
  J[1] = -k * c * v[0] * v[0];
  J[2] = -k * c * v[1] * v[1];
  J[3] = k * c * v[0] * v[0];
}

void jacobianFGyrqDot(unsigned int n, double *q, double *v, double *J, unsigned int nz,
                      double *z)
{
  (void)n; (void)nz; (void)z;
  const double k = M2 * L1 * L2, s = sin(q[0] - q[1]);
  J[0] = 0.0;
  J[1] = -2.0 * k * s * v[0];
  J[2] = 2.0 * k * s * v[1];
  J[3] = 0.0;
}

void FInt(double t, unsigned int n, double *q, double *v, double *f, unsigned int nz, double *z)
{
  (void)t; (void)n; (void)v; (void)nz; (void)z;
  f[0] = (M1 + M2) * G * L1 * sin(q[0]);
  f[1] = M2 * G * L2 * sin(q[1]);
}

void jacobianFIntq(double t, unsigned int n, double *q, double *v, double *J, unsigned int nz,
                   double *z)
{
  (void)t; (void)n; (void)v; (void)nz; (void)z;
  J[0] = (M1 + M2) * G * L1 * cos(q[0]);
  J[1] = 0.0;
  J[2] = 0.0;
  J[3] = M2 * G * L2 * cos(q[1]);
}

void jacobianFIntqDot(double t, unsigned int n, double *q, double *v, double *J,
                      unsigned int nz, double *z)
{
  (void)t; (void)n; (void)q; (void)v; (void)nz; (void)z;
  J[0] = J[1] = J[2] = J[3] = 0.0;
}

void h0(unsigned int n, double *q, unsigned int ny, double *y, unsigned int nz, double *z)
{
  (void)n; (void)ny; (void)nz; (void)z;
  y[0] = L1 * sin(q[0]);
}

void G0(unsigned int n, double *q, unsigned int ny, double *G0, unsigned int nz, double *z)
{
  (void)n; (void)ny; (void)nz; (void)z;
  G0[0] = L1 * cos(q[0]);
  G0[1] = 0.0;
}

void h1(unsigned int n, double *q, unsigned int ny, double *y, unsigned int nz, double *z)
{
  (void)n; (void)ny; (void)nz; (void)z;
  y[0] = L1 * sin(q[0]) + L2 * sin(q[1]);
}

void G1(unsigned int n, double *q, unsigned int ny, double *G1, unsigned int nz, double *z)
{
  (void)n; (void)ny; (void)nz; (void)z;
  G1[0] = L1 * cos(q[0]);
  G1[1] = L2 * cos(q[1]);
}
