"""The reference values of tests/sims/acrobot/acrobot_test.cpp: Gymnasium
Acrobot-v1's update ("book" dynamics) transcribed from
gymnasium/envs/classic_control/acrobot.py (_dsdt, rk4, wrap, bound) in numpy, run
for fixed action sequences. Gymnasium itself is not packaged in Debian 12;
`/usr/bin/python3 tests/sims/acrobot/gymnasium_acrobot_reference.py` prints the
states the test holds."""
import numpy as np
from numpy import sin, cos, pi
LINK_LENGTH_1=1.0; LINK_MASS_1=1.0; LINK_MASS_2=1.0; LINK_COM_POS_1=0.5; LINK_COM_POS_2=0.5; LINK_MOI=1.0
MAX_VEL_1=4*pi; MAX_VEL_2=9*pi; dt=0.2
def _dsdt(s_augmented):
    m1=LINK_MASS_1; m2=LINK_MASS_2; l1=LINK_LENGTH_1; lc1=LINK_COM_POS_1; lc2=LINK_COM_POS_2; I1=LINK_MOI; I2=LINK_MOI; g=9.8
    a=s_augmented[-1]; s=s_augmented[:-1]
    theta1=s[0]; theta2=s[1]; dtheta1=s[2]; dtheta2=s[3]
    d1 = m1*lc1**2 + m2*(l1**2 + lc2**2 + 2*l1*lc2*cos(theta2)) + I1 + I2
    d2 = m2*(lc2**2 + l1*lc2*cos(theta2)) + I2
    phi2 = m2*lc2*g*cos(theta1 + theta2 - pi/2.0)
    phi1 = (-m2*l1*lc2*dtheta2**2*sin(theta2) - 2*m2*l1*lc2*dtheta2*dtheta1*sin(theta2) + (m1*lc1 + m2*l1)*g*cos(theta1 - pi/2) + phi2)
    ddtheta2 = (a + d2/d1*phi1 - m2*l1*lc2*dtheta1**2*sin(theta2) - phi2) / (m2*lc2**2 + I2 - d2**2/d1)
    ddtheta1 = -(d2*ddtheta2 + phi1)/d1
    return dtheta1, dtheta2, ddtheta1, ddtheta2, 0.0
def rk4(derivs, y0, t):
    Ny=len(y0); yout=np.zeros((len(t),Ny)); yout[0]=y0
    for i in np.arange(len(t)-1):
        this=t[i]; dt_=t[i+1]-this; dt2=dt_/2.0; y0=yout[i]
        k1=np.asarray(derivs(y0)); k2=np.asarray(derivs(y0+dt2*k1)); k3=np.asarray(derivs(y0+dt2*k2)); k4=np.asarray(derivs(y0+dt_*k3))
        yout[i+1]=y0+dt_/6.0*(k1+2*k2+2*k3+k4)
    return yout[-1][:4]
def wrap(x,m,M):
    diff=M-m
    while x>M: x=x-diff
    while x<m: x=x+diff
    return x
def bound(x,m,M): return min(max(x,m),M)
def run(s, acts, show):
    s=np.array(s)
    for k,a in enumerate(acts):
        torque=[-1.0,0.0,1.0][a]
        ns=rk4(_dsdt,np.append(s,torque),[0,dt])
        ns[0]=wrap(ns[0],-pi,pi); ns[1]=wrap(ns[1],-pi,pi); ns[2]=bound(ns[2],-MAX_VEL_1,MAX_VEL_1); ns[3]=bound(ns[3],-MAX_VEL_2,MAX_VEL_2)
        s=ns
        term = bool(-cos(s[0]) - cos(s[1]+s[0]) > 1.0)
        if k in show: print(k, '{%s}'%', '.join('%.17g'%x for x in s), term)
run([0.05,-0.03,0.02,-0.01],[2,2,0,0,1,2,0,2,2,2,0,0,2,2,1,0,2,0,2,2],(0,4,9,19))
run([3.1,-3.1,12.0,-27.0],[2,2,0,1,2],(0,1,2,3,4))
