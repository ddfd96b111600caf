"""Child of cpu_ab.py: CPU time (process_time) of translate(FILE): first call and median of warm repeats."""
import sys, time, json
from symlearn.logic.ltlf.tlsf import load_tlsf
from symlearn.logic.ltlf.to_dfa import translate
import symlearn.logic.ltlf.composition  # noqa
f = load_tlsf(sys.argv[1]).formula
reps = int(sys.argv[2])
t = time.process_time(); translate(f); first = time.process_time() - t
ws = []
for _ in range(reps):
    t = time.process_time(); translate(f); ws.append(time.process_time() - t)
ws.sort()
print(json.dumps({"first": first, "warm": ws[len(ws) // 2]}))
