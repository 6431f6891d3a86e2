#!/usr/bin/env python3
"""Does the non-symmetric part of LIGGGHTS' Hertz tangential law make an
undamped pile grow below the symmetric model's limit?

For Hertz, k_t = 8 G* sqrt(R* delta) while the shear s is stored as a
displacement, so the tangential force -k_t s changes with the overlap:
dF_t = (k_t / (2 delta)) s d(delta) (pairs and walls).  This adds the
non-symmetric K_x = -(k_t / 2 delta) G_t^T s G_n to reference_damped.py's
symmetric K.  The script runs the one-step map u' = u - h (A x + B u),
x' = x + h u' with and without K_x from a random start and prints |u|^2 every tenth of the run.

Usage: python3 history_coupling_check.py SCENE STEPS DT [DT ...]
e.g.   python3 history_coupling_check.py e_undamped 20000 7.0e-5 7.28e-5 7.45e-5
"""
import os
import sys

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import reference_damped as R
sc=sys.argv[1]; steps=int(sys.argv[2]); hs=[float(x) for x in sys.argv[3:]]
A,B,st,n=R.assemble(sc,'stick')
# extra non-symmetric term: dF_t = (kt/(2 delta)) s G_n q  (Hertz kt ~ sqrt(delta))
import json
d=os.path.join(R.DATA,sc); mat=json.load(open(os.path.join(d,'materials.json'))); M=R.Material(mat)
p=R.read_csv(os.path.join(d,'particles.csv')); x=np.c_[p['x'],p['y'],p['z']]; rad=p['radius']; mass=p['mass']
row={int(i):k for k,i in enumerate(p['id'])}
I_=[];J_=[];V_=[]
c=R.read_csv(os.path.join(d,'pairs.csv'))
def add(dofs, Mblk):
    a,b=np.meshgrid(dofs,dofs,indexing='ij'); I_.append(a.ravel()); J_.append(b.ravel()); V_.append(Mblk.ravel())
for k in range(len(c['id1'])):
    a,b=row[int(c['id1'][k])],row[int(c['id2'][k])]
    dv=x[a]-x[b]; r=np.linalg.norm(dv); delta=rad[a]+rad[b]-r; nv=dv/r
    reff=rad[a]*rad[b]/(rad[a]+rad[b]); meff=mass[a]*mass[b]/(mass[a]+mass[b])
    Fn,kn,kt,gn,gt=M.contact(reff,meff,delta)
    s=np.array([c['shear_x'][k],c['shear_y'][k],c['shear_z'][k]])
    ci,cj=rad[a]-delta/2,rad[b]-delta/2
    P=np.eye(3)-np.outer(nv,nv); X=R.cross_matrix(nv)
    Gt=np.c_[P,ci*X,-P,cj*X]; Gn=np.r_[nv,np.zeros(3),-nv,np.zeros(3)][None,:]
    dofs=np.r_[6*a+np.arange(6),6*b+np.arange(6)]
    # Q = -K q ; dQ = Gt^T (kt/(2 delta)) s Gn q  => K_extra = -(kt/(2delta)) Gt^T s Gn
    add(dofs, -(kt/(2*delta))*Gt.T@np.outer(s,Gn[0]))
w=R.read_csv(os.path.join(d,'walls.csv'))
for k in range(len(w['id'])):
    a=row[int(w['id'][k])]; ax='xyz'.index(w['axis'][k]); nv=np.zeros(3); nv[ax]=float(w['normal_sign'][k]); delta=float(w['delta'][k])
    Fn,kn,kt,gn,gt=M.contact(rad[a],mass[a],delta)
    s=np.array([w['shear_x'][k],w['shear_y'][k],w['shear_z'][k]])
    cr=rad[a]-delta/2; P=np.eye(3)-np.outer(nv,nv); X=R.cross_matrix(nv)
    Gt=np.c_[P,cr*X]; Gn=np.r_[nv,np.zeros(3)][None,:]
    add(6*a+np.arange(6), -(kt/(2*delta))*Gt.T@np.outer(s,Gn[0]))
N=A.shape[0]
Kx=sp.coo_matrix((np.concatenate(V_),(np.concatenate(I_),np.concatenate(J_))),shape=(N,N)).tocsr()
inertia=0.4*mass*rad**2; md=np.c_[mass,mass,mass,inertia,inertia,inertia].ravel(); S=sp.diags(1/np.sqrt(md))
Ax=(S@Kx@S).tocsr()
print('||Ax||/||A|| (fro)', sp.linalg.norm(Ax)/sp.linalg.norm(A))
rng=np.random.default_rng(2)
for h in hs:
  for label,AA in (('sym',A),('sym+history',A+Ax)):
    xx=np.zeros(N); v=rng.standard_normal(N); e=[]
    for kk in range(steps):
        v=v-h*(AA@xx+B@v); xx=xx+h*v
        if kk%(steps//10)==0: e.append(v@v)
    print(sc, label, h, ' '.join('%.2e'%q for q in e), '%.2e'%(v@v))
