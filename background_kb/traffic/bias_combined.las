% Combined junction: language bias (constraints only, no #modeh), the union of both variants'.
#constant(direction, zero).
#constant(direction, north).
#constant(direction, east).
#constant(direction, south).
#constant(direction, west).

#modeb(1, onRoad(const(direction))).
#modeb(1, beforeJunction(const(direction)), (positive)).
#modeb(1, go(const(direction))).
#modeb(1, tls0, (positive)).
#modeb(1, tls1, (positive)).
#modeb(1, carOnTheRight).
% "the agent is on no road": not onRoad(V) for every V with dir(V); V is local to the literal
#modec(1, not onRoad(var(dir)) : dir(var(dir))).
#maxv(1).
