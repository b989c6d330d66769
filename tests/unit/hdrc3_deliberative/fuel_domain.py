"""A resource domain for the planner's tests: a craft hops or jumps on fuel, lands on little.

``FUEL_PROBLEM``'s ``GOAL`` is replaced by each test's goal; a goal or precondition that wants
less fuel is what the cycle check's better-or-equal comparison must not prune.
"""

FUEL_DOMAIN = """domain hops
type spot
type craft
predicate at(c: craft, s: spot)
predicate road(a: spot, b: spot)
predicate landed(c: craft)
resource fuel(c: craft)
operator hop(c: craft, a: spot, b: spot)
  agent c
  pre at(c, a) and road(a, b) and fuel(c) >= 1
  effect [t'] not at(c, a), at(c, b), fuel(c) -= 1
end
operator jump(c: craft, a: spot, b: spot)
  agent c
  pre at(c, a) and road(a, b) and fuel(c) >= 2
  effect [t'] not at(c, a), at(c, b), fuel(c) -= 2
end
operator land(c: craft, s: spot)
  agent c
  pre at(c, s) and fuel(c) <= 38
  effect [t'] landed(c)
end
"""
FUEL_PROBLEM = """problem h for hops
object a, b: spot
object s: craft
init at(s, a), road(a, b), fuel(s) = 40
goal GOAL
"""
