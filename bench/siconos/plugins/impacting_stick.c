/* Siconos plugins for the impacting stick (models/siconos/impacting-stick.toml, the port of
 * ImpactingStick/ImpactingStick.cpp with ImpactingStickPlugin.cpp), from the model file, with
 * q = (x, y, th) and l the stick's length:
 *
 *   h  = y - l/2 cos(th)                      (the lower end's height, the plugin's h1)
 *   G  = [ 0   1  l/2 sin(th) ]               (dh/dq)
 *        [ -1  0  -l/2 cos(th) ]              (the tangential row, the plugin's G1: minus the
 *                                              file's slip row [1 0 l/2 cos(th)])
 *
 * for Siconos's LagrangianScleronomousR with NewtonImpactFrictionNSL (y has two rows, normal
 * then tangential; G is column-major, 2 x 3). l is compiled in from the file (-DLEN=).
 * Signatures: (n, q, ny, out, nz, z).
 */
#include <math.h>

void h1(unsigned int n, double *q, unsigned int ny, double *y, unsigned int nz, double *z)
{
  (void)n; (void)nz; (void)z;
  y[0] = q[1] - 0.5 * LEN * cos(q[2]);
  if (ny > 1)
    y[1] = 0.0;
}

void G1(unsigned int n, double *q, unsigned int ny, double *G, unsigned int nz, double *z)
{
  (void)n; (void)nz; (void)z;
  if (ny == 1) {
    G[0] = 0.0;
    G[1] = 1.0;
    G[2] = 0.5 * LEN * sin(q[2]);
    return;
  }
  G[0] = 0.0;
  G[1] = -1.0;
  G[2] = 1.0;
  G[3] = 0.0;
  G[4] = 0.5 * LEN * sin(q[2]);
  G[5] = -0.5 * LEN * cos(q[2]);
}
