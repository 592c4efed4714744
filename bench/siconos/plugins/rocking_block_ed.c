/* Siconos plugins for the block dropped flat onto its two corners
 * (models/siconos/rocking-block-ed.toml, the port of RockingBlock/RockingBlockED.cpp), from the
 * model file's constraints, with q = (x, y, theta), L the block's length and H its height:
 *
 *   corner1 = y - L/2 sin(theta) - H/2 cos(theta)
 *   corner2 = y + L/2 sin(theta) - H/2 cos(theta)
 *
 * h, G = dh/dq and dotG = d/dt(dh/dq) for Siconos's LagrangianScleronomousR; L and H are
 * compiled in from the file (-DLEN= -DHEIGHT=). Signatures: h and G (n, q, ny, out, nz, z),
 * dotG (n, q, nv, v, out, nz, z); G and dotG are 1 x 3 rows.
 */
#include <math.h>

static void corner_h(double s, const double *q, double *y)
{
  y[0] = q[1] + s * 0.5 * LEN * sin(q[2]) - 0.5 * HEIGHT * cos(q[2]);
}

static void corner_G(double s, const double *q, double *G)
{
  G[0] = 0.0;
  G[1] = 1.0;
  G[2] = s * 0.5 * LEN * cos(q[2]) + 0.5 * HEIGHT * sin(q[2]);
}

static void corner_dotG(double s, const double *q, const double *v, double *dG)
{
  dG[0] = 0.0;
  dG[1] = 0.0;
  dG[2] = (-s * 0.5 * LEN * sin(q[2]) + 0.5 * HEIGHT * cos(q[2])) * v[2];
}

void h1(unsigned int n, double *q, unsigned int ny, double *y, unsigned int nz, double *z)
{
  (void)n; (void)ny; (void)nz; (void)z;
  corner_h(-1.0, q, y);
}

void G1(unsigned int n, double *q, unsigned int ny, double *G, unsigned int nz, double *z)
{
  (void)n; (void)ny; (void)nz; (void)z;
  corner_G(-1.0, q, G);
}

void G1dot(unsigned int n, double *q, unsigned int nv, double *v, double *dG, unsigned int nz,
           double *z)
{
  (void)n; (void)nv; (void)nz; (void)z;
  corner_dotG(-1.0, q, v, dG);
}

void h2(unsigned int n, double *q, unsigned int ny, double *y, unsigned int nz, double *z)
{
  (void)n; (void)ny; (void)nz; (void)z;
  corner_h(1.0, q, y);
}

void G2(unsigned int n, double *q, unsigned int ny, double *G, unsigned int nz, double *z)
{
  (void)n; (void)ny; (void)nz; (void)z;
  corner_G(1.0, q, G);
}

void G2dot(unsigned int n, double *q, unsigned int nv, double *v, double *dG, unsigned int nz,
           double *z)
{
  (void)n; (void)nv; (void)nz; (void)z;
  corner_dotG(1.0, q, v, dG);
}
