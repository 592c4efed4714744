"""The shipped models with friction against their closed forms and references, at the default
tolerance, through the release binary (`cargo build --release -p zenosim-cli` first): the largest
error of each and the wall time of its `zenosim run` (process start and output included).
Closed forms: docs/friction.md and each model file's header; Housner's block against
models/references/housner-block.json (bench/references/housner.py).

Run: python3 bench/friction.py
"""
import tempfile
import json, math, subprocess, time
import os, sys
ROOT=os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
Z=os.path.join(ROOT,'target','release','zenosim')
OUT=tempfile.mkdtemp(prefix='zenosim-friction-')
G=9.81
def run(model, *args):
    out=os.path.join(OUT,'ff-')+model+'-'+'-'.join(a.replace('=','') for a in args if not a.startswith('--'))
    t0=time.perf_counter()
    subprocess.run([Z,'run',os.path.join(ROOT,'models','')+model+'.toml','--out',out,*args],capture_output=True)
    wall=time.perf_counter()-t0
    return json.load(open(out+'/summary.json')), wall
res={}
# ball sticks
d,w=run('ball-backspin')
r,e,y0,v0,w0=0.1,0.5,1.0,1.0,-20.0
t1=math.sqrt(2*(y0-r)/G); tz=t1*(1+e)/(1-e); roll=(5*v0-2*r*w0)/7
imp=[x for x in d['events'] if x['kind']=='impact']
res['ball sticks']=dict(first_impact=abs(imp[0]['t']-t1), rolling_after=abs(imp[0]['after']['q_dot'][0]-roll), zeno=abs(d['zeno'][0]['t_zeno']-tz), final=abs(d['final']['q_dot'][0]-roll), wall=w)
d,w=run('ball-backspin','--set','mu=0.02')
mu=0.02; v1=G*t1; sz=v0+r*w0+3.5*mu*(1+e)*v1/(1-e); ts=tz+abs(sz)/(3.5*mu*G)
st=[x['t'] for x in d['events'] if x['kind']=='stick']
res['ball slides']=dict(zeno=abs(d['zeno'][0]['t_zeno']-tz), stick=abs(st[0]-ts), final=abs(d['final']['q_dot'][0]-roll), wall=w)
d,w=run('rough-incline')
a=0.3; dec=G*(0.5*math.cos(a)-math.sin(a)); tstop=2/dec
res['incline stops']=dict(stop=abs(d['events'][0]['t']-tstop), x=abs(d['final']['q'][0]-(2*tstop-0.5*dec*tstop**2)), wall=w)
d,w=run('rough-incline','--set','mu=0.2')
acc=G*(math.sin(a)-0.2*math.cos(a))
res['incline slides']=dict(x=abs(d['final']['q'][0]-(2*3+0.5*acc*9)), v=abs(d['final']['q_dot'][0]-(2+3*acc)), wall=w)
d,w=run('belt-stick-slip')
k,vb,ms,mk=4.0,0.5,0.6,0.4; om=2.0; c=mk*G/k
tst=math.asin(vb/(c*om))/om; xst=c*(1-math.cos(om*tst)); xsl=ms*G/k; tsl=tst+(xsl-xst)/vb
ph=math.atan2(-vb/om, xsl-c); tau=((-math.pi-2*ph)/om)%(2*math.pi/om); per=tau+2*(xsl-c)/vb
exp=[tst,tsl,tsl+tau,tsl+per,tsl+tau+per]
got=[x['t'] for x in d['events']]
res['belt']=dict(events=max(abs(a-b) for a,b in zip(got,exp)), n=len(got), residual=d['energy_balance']['residual'], wall=w)
d,w=run('housner-block')
ref=json.load(open(os.path.join(ROOT,'models','references','housner-block.json')))
imp=[x['t'] for x in d['events'] if x['kind']=='impact']
res['housner']=dict(impacts=max(abs(a-float(b)) for a,b in zip(imp,ref['impacts'])), zeno=abs(d['zeno'][0]['t_zeno']-float(ref['t_zeno'])), n=len(imp), wall=w)
d,w=run('rimless-wheel')
m,I,l,ga=1.0,0.1,1.0,0.1; a=math.pi/10
r=(I+m*l*l*math.cos(2*a))/(I+m*l*l); K=4*m*G*l*math.sin(a)*math.sin(ga)/(I+m*l*l); ws=math.sqrt(r*r*K/(1-r*r))
imp=[x for x in d['events'] if x['kind']=='impact']
res['rimless wheel']=dict(ratio=max(abs(x['after']['q_dot'][2]/x['before']['q_dot'][2]-r) for x in imp),
    stance_gain=max(abs(y['before']['q_dot'][2]**2-x['after']['q_dot'][2]**2-K)/K for x,y in zip(imp,imp[1:])),
    last_to_cycle=abs(abs(imp[-1]['after']['q_dot'][2])-ws), n=len(imp), wall=w)
d,w=run('sphere-slide-spin')
u0=(2.0-0.1*-15.0, 0.5+0.1*10.0); ts=math.hypot(*u0)/(3.5*0.3*G)
st=[x['t'] for x in d['events'] if x['kind']=='stick']; v=d['final']['q_dot']
res['sphere in space']=dict(stick=abs(st[0]-ts), vx=abs(v[0]-(2.0-2/7*u0[0])), vy=abs(v[1]-(0.5-2/7*u0[1])), spin_z=abs(v[5]-7.0), wall=w)
d,w=run('dumbbell-landing')
m,l,h,e,mu,v,om=1.0,2.0,0.05,0.5,0.5,1.0,1.0; t1=math.sqrt(2*h/G); N=(1+e)*m*math.sqrt(2*G*h)
imp=[x for x in d['events'] if x['kind']=='impact']; a=imp[0]['after']['q_dot']
want=[0.0, v-mu*N/(2*m), e*G*t1, 0.0, om-mu*N/(m*l)]
res['dumbbell in space']=dict(first_impact=abs(imp[0]['t']-t1), after=max(abs(x-y) for x,y in zip(a,want)),
    zeno=abs(d['zeno'][0]['t_zeno']-t1*(1+e)/(1-e)), final=max(abs(x) for x in d['final']['q_dot']), wall=w)
d,w=run('painleve-rod')
res['painleve']=dict(status=d['status'], t=d['final']['t'], msg=d['message'][:90], wall=w)
for k,v in res.items(): print(k, {a:(('%.1e'%b) if isinstance(b,float) else b) for a,b in v.items()})
