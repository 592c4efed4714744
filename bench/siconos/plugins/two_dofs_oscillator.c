/* Siconos plugin for the forced two-mass friction oscillator
 * (models/siconos/two-dofs-friction-oscillator.toml, the port of
 * FrictionOscillator/TwoDofsFrictionOscillator.py): the forcing b(t) of its first-order system
 * x = (x1, x1', x2, x2'), as the example's TwoDofsOscillatorB (plugins/OscillatorPlugin.cpp)
 * has it but without its printing at every call:
 *
 *   b = (0, f1 cos(w t), 0, 0)
 *
 * f1 and w are compiled in from the file's [forces] (-DF1= -DOMEGA=). Signature of a
 * FirstOrderLinearDS's b: (t, n, b, nz, z).
 */
#include <math.h>

void TwoDofsOscillatorB(double time, unsigned int n, double *b, unsigned int nz, double *z)
{
  (void)nz; (void)z;
  for (unsigned int i = 0; i < n; i++)
    b[i] = 0.0;
  b[1] = F1 * cos(OMEGA * time);
}
