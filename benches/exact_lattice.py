"""An oracle for `discover` independent of the tool: recordings of the lattice Langevin beam
u'' = -c D4 u - 2c' D4 u' + a A3 u + xi (D4 = SᵀS the free beam's operator, A3 the centred third
difference, off where it would leave the body), the bending modes' linear SDE propagated from
frame to frame exactly (matrix exponential, covariance from the Lyapunov equation), written as
tracked midlines (head first, each frame's line removed, tracking noise a share of the bending).

Usage: python benches/exact_lattice.py out=REC.csv [c=660 cp=20 a=60 frames=150001 seed=1 noise=0.01]
(grid units, N = 25, frames 0.05 apart); then `theory-search discover REC.csv --model
tables/models/crawler.toml -p 25 --active`. docs/discover.md gives what it found.
"""
import sys, numpy as np, scipy.linalg as sl
args = dict(a.split('=',1) for a in sys.argv[1:])
N=25; c=float(args.get('c',660)); cp=float(args.get('cp',20)); a=float(args.get('a',60)); kT=1.0
frames=int(args.get('frames',150001)); dt=0.05; seed=int(args.get('seed',1))
S=np.zeros((N-2,N))
for i in range(N-2): S[i,i:i+3]=[1,-2,1]
D4=S.T@S
A=np.zeros((N,N))
for i in range(2,N-2): A[i,i-2:i+3]=[-0.5,1,0,-1,0.5]
K=c*D4; C=2*cp*D4
lam,W=np.linalg.eigh(D4); Vb=W[:,2:]          # bending modes (rigid ones never feed back)
m=N-2
Kb=Vb.T@(K-a*A)@Vb; Cb=Vb.T@C@Vb
M=np.block([[np.zeros((m,m)),np.eye(m)],[-Kb,-Cb]])
GG=np.zeros((2*m,2*m)); GG[m:,m:]=2*kT*Cb
P=sl.solve_continuous_lyapunov(M,-GG)
Ad=sl.expm(M*dt); Q=P-Ad@P@Ad.T
Q=(Q+Q.T)/2; qw,qv=np.linalg.eigh(Q); qw[qw<0]=0; L=qv*np.sqrt(qw)
rng=np.random.default_rng(seed)
z=np.linalg.cholesky(P+1e-15*np.eye(2*m))@rng.standard_normal(2*m); out=np.empty((frames,N))
for k in range(frames):
    out[k]=Vb@z[:m]; z=Ad@z+L@rng.standard_normal(2*m)
h=1/(N-1); s=np.arange(N)*h
y=out*h; Ab=np.vstack([np.ones(N),s]).T
res=y-(y@np.linalg.pinv(Ab).T)@Ab.T
sig=float(args.get('noise',0.01))*res.std()
X=np.tile(s,(frames,1))+rng.normal(0,sig,res.shape); Y=res+rng.normal(0,sig,res.shape)
t=np.arange(frames)*dt
with open(args.get('out','ex.csv'),'w') as f:
    for k in range(frames):
        row=[t[k]]
        for i in reversed(range(N)): row+=[X[k,i],Y[k,i]]
        f.write(','.join(f'{v:.10g}' for v in row)+'\n')
print('rms bend', res.std())
