"""Perfect-model check of a dumped forecast skill run: each member in turn is the truth against the other
members (p >= 0.5, predicted time the median of their snap times, +-1.5 s), beside the same per-forecast
score against the real run. Usage: forecast_perfect_model.py DUMP.json [...]"""
import json, sys, math, statistics as st
from collections import defaultdict
tol=1.5
for path in sys.argv[1:]:
    d=json.load(open(path)); M=d['args']['members']
    for r in d['runs']:
        mins=d['args']['minutes']
        for end in ('ship','vehicle'):
            fcs=[x for x in r['forecasts']['known_sea'] if x[0]==end]
            if not fcs: continue
            real=[t for e,t in r['snaps'] if e==end]
            # real scorer (same per-forecast rule)
            ra=rf=0; rel_real=defaultdict(lambda:[0,0]); rel_pm=defaultdict(lambda:[0,0])
            pa=pf=0.0
            for x in fcs:
                stamp,p,snaps=x[1],x[2],[s[0] for s in x[5]]
                H=d['args']['horizon']
                hit=any(stamp<t<=stamp+H for t in real)
                b=min(int(p*M),M-1) if p<1 else M-1
                rel_real[round(p,3)][0]+=1; rel_real[round(p,3)][1]+=hit
                if p>=0.5 and snaps:
                    tp=st.median(snaps); ra+=1
                    if not any(abs(t-tp)<=tol for t in real): rf+=1
                # perfect model: hold out each member
                n=len(snaps)
                for k in range(M):
                    if k<n: truth=[snaps[k]]; others=snaps[:k]+snaps[k+1:]
                    else: truth=[]; others=snaps
                    po=len(others)/(M-1)
                    rel_pm[round(po,2)][0]+=1/M; rel_pm[round(po,2)][1]+=(len(truth)>0)/M
                    if po>=0.5:
                        tp=st.median(others); pa+=1/M
                        if not any(abs(t-tp)<=tol for t in truth): pf+=1/M
            print(f"{path.split('/')[-1]} seed {r['seed']} {end}: per-forecast alarms real {ra} false {rf} ({rf/max(ra,1):.2f}); perfect-model alarms {pa:.1f} false {pf:.1f} ({pf/max(pa,1e-9):.2f}); per 10 min: real {rf/mins*10:.1f}, pm {pf/mins*10:.1f}")
