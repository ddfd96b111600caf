% Towers of Hanoi: language bias (constraints only, no #modeh).
% on(V1, V2) over disk variables and comparisons between disk variables.
#modeb(1, on(var(disk), var(disk))).
#modeb(1, var(disk) = var(disk)).
#modeb(1, var(disk) < var(disk)).
#modeb(1, var(disk) > var(disk)).
#maxv(3).
