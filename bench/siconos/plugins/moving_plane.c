/* Siconos plugin for the ball on a moving plane (models/siconos/ball-on-moving-plane.toml, the
 * port of BallOnMovingPlane/BallOnMovingPlane.cpp): the plane's prescribed velocity
 * v(t) = C + A cos(w t), the time derivative of the file's plane height C t + A/w sin(w t).
 * C, A and w are compiled in from the file (-DVC= -DVA= -DVW=). Signature of Siconos's
 * BoundaryCondition plugin: (t, size, out).
 */
#include <math.h>

void prescribedvelocity(double t, unsigned int n, double *v)
{
  (void)n;
  v[0] = VC + VA * cos(VW * t);
}
