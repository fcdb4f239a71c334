"""Issue 47, hills: -2 ln L of the bump model hxai sr selects, the linear law and the law with an
intercept under Gaussian, Student-t (1, 2, 4, 8 df) and Laplace errors, the scale fitted by
maximum likelihood. Run from the repository root: python scripts/hills_likelihoods.py
(docs/benchmarks.md, "The defaults on a quiet machine")."""
import numpy as np, csv
from scipy.special import gammaln
rows=list(csv.DictReader(open('testdata/real/hills.csv')))
d=np.array([float(r['dist']) for r in rows]); c=np.array([float(r['climb']) for r in rows]); y=np.array([float(r['time']) for r in rows])
n=len(y)
def law(): 
    A=np.c_[d,c]; b=np.linalg.lstsq(A,y,rcond=None)[0]; return A@b
def lin3():
    A=np.c_[d,c,np.ones(n)]; b=np.linalg.lstsq(A,y,rcond=None)[0]; return A@b
tangle=-2622*(np.exp(-((-0.003*d - 0.5)**2 + (3.000e-5*c)**2)) - np.exp(-(0.0373*c - 15)**2)) + 2039
from scipy.optimize import minimize_scalar
def t_m2ll(r,nu):
    def f(ls):
        s=np.exp(ls)
        return -2*np.sum(gammaln((nu+1)/2)-gammaln(nu/2)-0.5*np.log(nu*np.pi)-np.log(s)-(nu+1)/2*np.log1p(r**2/(nu*s*s)))
    res=minimize_scalar(f,bounds=(np.log(np.std(r))-10,np.log(np.std(r))+3),method='bounded')
    return res.fun
def g_m2ll(r): return n*np.log(2*np.pi*np.mean(r**2))+n
for name,p in [('law',law()),('lin3',lin3()),('tangle',tangle)]:
    r=y-p
    print(name, 'mse',np.mean(r**2),'gauss',g_m2ll(r), *['t%d %.1f'%(nu,t_m2ll(r,nu)) for nu in (1,2,4,8)], 'laplace', 2*n*np.log(2*np.mean(abs(r)))+2*n)
