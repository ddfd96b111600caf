"""Child of wall_ab.py: time one translate() of FILE in a fresh process (imports before the clock, as ltl dfa does)."""
import sys, time, json
from symlearn.logic.ltlf.tlsf import load_tlsf
from symlearn.logic.ltlf.to_dfa import translate
import symlearn.logic.ltlf.composition  # noqa
f = load_tlsf(sys.argv[1]).formula
t = time.perf_counter(); d = translate(f); s = time.perf_counter() - t
edges = None if d.is_symbolic() or d.n_states > 300 else [[(str(g), t) for g, t in d.successors(q)] for q in d.states]
import hashlib
print(json.dumps({"s": s, "states": d.n_states, "digest": hashlib.sha1(json.dumps([sorted(d.accepting), edges]).encode()).hexdigest()}))
