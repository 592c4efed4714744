// Siconos's D1MinusLinearOSI time-stepping for the suite (suite.py, siconos_side.py): the
// Python bindings of Debian's python3-siconos 4.4 have no D1MinusLinearOSI nor
// TimeSteppingD1Minus, so the examples that use them (the slider-crank with clearance, the
// impacting bar) run through this small program, compiled at run time against
// libsiconos_kernel. It builds the same model as siconos_side.build from a plain-text job that
// siconos_side.py writes (every number from the model file), runs it and writes what
// siconos_side.run_once records, as JSON.
//
// Job (whitespace-separated):
//   t0 t_end h type(0 halfexplicit_acceleration_level, 3 halfexplicit_velocity_level)
//   repeats progress_path out_path
//   nds, then per DS: kind(0 linear, 1 plugin) n q0[n] v0[n]
//     linear: mass[n*n, row-major] hasK [K[n*n]] fext[n]
//     plugin: lib mass FGyr jacobianFGyrq jacobianFGyrqDot FInt jacobianFIntq jacobianFIntqDot
//             hasFext [fext[n]]
//   ninter, then per interaction: e nds ds[nds] kind(0 linear, 1 plugin)
//     linear: size C[size] offset      plugin: lib h G0 dotG0 ('-' for none)
//
// Output: {"status", "reason", "t_reached", "steps", "events_truncated" (more than 100000
// steps with an impulse or a contact force: the first 100000 kept), "events": [{"k", "t",
// "t_start", "q", "v_before", "v_after", "impulse": [lambda(1) per interaction], "force":
// [lambda(2) per interaction]}] (every step with a positive one), "final": {"t", "q", "q_dot",
// "lambda"}, "wall_time_s": [per repeat]}; the first repeat records events, the others are
// timed only.
#include <siconos/kernel/SiconosKernel.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

struct Job {
  double t0, t_end, h;
  int type, repeats;
  std::string progress, out;
  std::string text;  // the rest, re-read per repeat
};

static std::string vec(const SiconosVector &v) {
  std::ostringstream o;
  o.precision(17);
  o << "[";
  for (unsigned i = 0; i < v.size(); i++) o << (i ? ", " : "") << v(i);
  o << "]";
  return o.str();
}

static std::string vecs(const std::vector<SP::SiconosVector> &vs) {
  std::string s = "[";
  for (size_t i = 0; i < vs.size(); i++) s += (i ? ", " : "") + vec(*vs[i]);
  return s + "]";
}

static std::string json_escape(const std::string &s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (c == '\n') { o += "\\n"; continue; }
    o += c;
  }
  return o;
}

struct Built {
  std::vector<SP::LagrangianDS> ds;
  std::vector<SP::Interaction> inter;
  SP::TimeSteppingD1Minus sim;
};

static Built build(const Job &job) {
  std::istringstream in(job.text);
  Built b;
  SP::NonSmoothDynamicalSystem nsds(new NonSmoothDynamicalSystem(job.t0, job.t_end));
  int nds;
  in >> nds;
  for (int k = 0; k < nds; k++) {
    int kind, n;
    in >> kind >> n;
    SP::SiconosVector q0(new SiconosVector(n)), v0(new SiconosVector(n));
    for (int i = 0; i < n; i++) in >> (*q0)(i);
    for (int i = 0; i < n; i++) in >> (*v0)(i);
    SP::LagrangianDS ds;
    if (kind == 0) {
      SP::SimpleMatrix M(new SimpleMatrix(n, n));
      for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) in >> (*M)(i, j);
      SP::LagrangianLinearTIDS lin(new LagrangianLinearTIDS(q0, v0, M));
      int hasK;
      in >> hasK;
      if (hasK) {
        SP::SimpleMatrix K(new SimpleMatrix(n, n));
        for (int i = 0; i < n; i++)
          for (int j = 0; j < n; j++) in >> (*K)(i, j);
        lin->setKPtr(K);
      }
      SP::SiconosVector f(new SiconosVector(n));
      for (int i = 0; i < n; i++) in >> (*f)(i);
      lin->setFExtPtr(f);
      ds = lin;
    } else {
      std::string lib, fmass, names[6];
      in >> lib >> fmass;
      for (auto &s : names) in >> s;
      ds.reset(new LagrangianDS(q0, v0, lib + ":" + fmass));
      if (names[0] != "-") ds->setComputeFGyrFunction(lib, names[0]);
      if (names[1] != "-") ds->setComputeJacobianFGyrqFunction(lib, names[1]);
      if (names[2] != "-") ds->setComputeJacobianFGyrqDotFunction(lib, names[2]);
      if (names[3] != "-") ds->setComputeFIntFunction(lib, names[3]);
      if (names[4] != "-") ds->setComputeJacobianFIntqFunction(lib, names[4]);
      if (names[5] != "-") ds->setComputeJacobianFIntqDotFunction(lib, names[5]);
      int hasF;
      in >> hasF;
      if (hasF) {
        SP::SiconosVector f(new SiconosVector(n));
        for (int i = 0; i < n; i++) in >> (*f)(i);
        ds->setFExtPtr(f);
      }
    }
    nsds->insertDynamicalSystem(ds);
    b.ds.push_back(ds);
  }
  int ni;
  in >> ni;
  for (int k = 0; k < ni; k++) {
    double e;
    int nlinked;
    in >> e >> nlinked;
    std::vector<int> linked(nlinked);
    for (auto &x : linked) in >> x;
    int kind;
    in >> kind;
    SP::Relation rel;
    if (kind == 0) {
      int size;
      in >> size;
      SP::SimpleMatrix C(new SimpleMatrix(1, size));
      for (int j = 0; j < size; j++) in >> (*C)(0, j);
      SP::SiconosVector off(new SiconosVector(1));
      in >> (*off)(0);
      rel.reset(new LagrangianLinearTIR(C, off));
    } else {
      std::string lib, h, g, gd;
      in >> lib >> h >> g >> gd;
      if (gd == "-")
        rel.reset(new LagrangianScleronomousR(lib + ":" + h, lib + ":" + g));
      else
        rel.reset(new LagrangianScleronomousR(lib + ":" + h, lib + ":" + g, lib + ":" + gd));
    }
    SP::Interaction inter(new Interaction(SP::NonSmoothLaw(new NewtonImpactNSL(e)), rel));
    if (nlinked == 1)
      nsds->link(inter, b.ds[linked[0]]);
    else
      nsds->link(inter, b.ds[linked[0]], b.ds[linked[1]]);
    b.inter.push_back(inter);
  }
  SP::TimeDiscretisation td(new TimeDiscretisation(job.t0, job.h));
  SP::D1MinusLinearOSI osi(new D1MinusLinearOSI(job.type));
  b.sim.reset(new TimeSteppingD1Minus(nsds, td, 2));
  b.sim->insertIntegrator(osi);
  b.sim->insertNonSmoothProblem(SP::OneStepNSProblem(new LCP()), SICONOS_OSNSP_TS_VELOCITY);
  b.sim->insertNonSmoothProblem(SP::OneStepNSProblem(new LCP()),
                                SICONOS_OSNSP_TS_VELOCITY + 1);
  return b;
}

static std::vector<SP::SiconosVector> copy_state(const Built &b, bool velocity) {
  std::vector<SP::SiconosVector> out;
  for (auto &ds : b.ds)
    out.push_back(SP::SiconosVector(new SiconosVector(velocity ? *ds->velocity() : *ds->q())));
  return out;
}

int main(int argc, char **argv) {
  if (argc != 2) {
    std::cerr << "usage: d1minus_runner JOB" << std::endl;
    return 2;
  }
  std::ifstream f(argv[1]);
  Job job;
  f >> job.t0 >> job.t_end >> job.h >> job.type >> job.repeats >> job.progress >> job.out;
  std::stringstream rest;
  rest << f.rdbuf();
  job.text = rest.str();
  std::ostringstream events;
  std::vector<double> walls;
  std::string status = "finished", reason;
  std::string final_json;
  double t_reached = job.t0;
  long steps = 0;
  const size_t keep = 100000;  // steps kept; beyond, events_truncated
  bool truncated = false;
  for (int r = 0; r < job.repeats; r++) {
    auto start = std::chrono::steady_clock::now();
    auto last = start;
    bool record = r == 0;
    size_t kept = 0;
    try {
      Built b = build(job);
      b.sim->initialize();
      long k = 0;
      while (b.sim->hasNextEvent()) {
        std::vector<SP::SiconosVector> qb, vb;
        double t_start = b.sim->startingTime();
        if (record) {
          qb = copy_state(b, false);
          vb = copy_state(b, true);
        }
        b.sim->advanceToEvent();
        k++;
        if (record) {
          bool any = false;
          std::ostringstream imp, force;
          imp.precision(17);
          force.precision(17);
          imp << "[";
          force << "[";
          for (size_t i = 0; i < b.inter.size(); i++) {
            double l = (*b.inter[i]->lambda(1))(0);
            // the contact force of the acceleration-level problem, which holds a closed
            // contact without an impulse
            SP::SiconosVector l2 = b.inter[i]->upperLevelForInput() >= 2
                                       ? b.inter[i]->lambda(2) : SP::SiconosVector();
            double f = l2 ? (*l2)(0) : 0.0;
            any = any || l > 0 || f > 0;
            imp << (i ? ", " : "") << l;
            force << (i ? ", " : "") << f;
          }
          imp << "]";
          force << "]";
          if (any && kept >= keep) truncated = true;
          if (any && kept < keep) {
            kept++;
            events.precision(17);
            events << (kept > 1 ? ",\n" : "") << "{\"k\": " << k
                   << ", \"t\": " << b.sim->nextTime() << ", \"t_start\": " << t_start
                   << ", \"q\": " << vecs(qb) << ", \"v_before\": " << vecs(vb)
                   << ", \"v_after\": " << vecs(copy_state(b, true))
                   << ", \"impulse\": " << imp.str() << ", \"force\": " << force.str() << "}";
          }
        }
        b.sim->processEvents();
        auto now = std::chrono::steady_clock::now();
        if (record && std::chrono::duration<double>(now - last).count() > 0.25) {
          last = now;
          std::ofstream p(job.progress);
          p.precision(17);
          p << "{\"t\": " << b.sim->startingTime() << ", \"steps\": " << k << "}";
        }
      }
      if (record) {
        steps = k;
        t_reached = b.sim->startingTime();
        std::ostringstream fj;
        fj.precision(17);
        std::string lam = "[";
        for (size_t i = 0; i < b.inter.size(); i++)
          lam += (i ? ", " : "") + vec(*b.inter[i]->lambda(1));
        lam += "]";
        fj << "{\"t\": " << t_reached << ", \"q\": " << vecs(copy_state(b, false))
           << ", \"q_dot\": " << vecs(copy_state(b, true)) << ", \"lambda\": " << lam << "}";
        final_json = fj.str();
      }
    } catch (...) {
      status = "failed";
      reason = "a Siconos exception in advanceToEvent";
      break;
    }
    walls.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::ofstream o(job.out);
  o.precision(17);
  o << "{\"status\": \"" << status << "\", \"reason\": "
    << (reason.empty() ? "null" : "\"" + json_escape(reason) + "\"")
    << ", \"t_reached\": " << t_reached << ", \"steps\": " << steps
    << ", \"events_truncated\": " << (truncated ? "true" : "false") << ", \"events\": [\n"
    << events.str() << "], \"final\": " << (final_json.empty() ? "null" : final_json)
    << ", \"wall_time_s\": [";
  for (size_t i = 0; i < walls.size(); i++) o << (i ? ", " : "") << walls[i];
  o << "]}\n";
  return 0;
}
