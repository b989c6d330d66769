; DriverLog, numeric version (IPC-2002), written for hdrc3 from the competition's description:
; the STRIPS domain plus static walking and driving times per footpath and road link, summed
; into (walked) and (driven), which the problem's metric weighs. The planner does not
; optimise the metric (TALplanner's model: a metric does not change which plans are valid).
; trucks drive along road links between junctions and need a driver on board; drivers walk
; along footpaths (through path points) and board or leave empty trucks; packages are loaded
; into and unloaded from trucks. Goals place packages, drivers and trucks.
(define (domain driverlog)
  (:requirements :strips :typing :numeric-fluents)
  (:types location locatable - object
          driver truck obj - locatable)
  (:predicates (at ?x - locatable ?l - location)
               (in ?o - obj ?t - truck)
               (driving ?d - driver ?t - truck)
               (link ?x ?y - location)
               (path ?x ?y - location)
               (empty ?t - truck))
  (:functions (time-to-walk ?x ?y - location)
              (time-to-drive ?x ?y - location)
              (driven)
              (walked))

  (:action load-truck
    :parameters (?o - obj ?t - truck ?l - location)
    :precondition (and (at ?t ?l) (at ?o ?l))
    :effect (and (not (at ?o ?l)) (in ?o ?t)))

  (:action unload-truck
    :parameters (?o - obj ?t - truck ?l - location)
    :precondition (and (at ?t ?l) (in ?o ?t))
    :effect (and (not (in ?o ?t)) (at ?o ?l)))

  (:action board-truck
    :parameters (?d - driver ?t - truck ?l - location)
    :precondition (and (at ?t ?l) (at ?d ?l) (empty ?t))
    :effect (and (not (at ?d ?l)) (driving ?d ?t) (not (empty ?t))))

  (:action disembark-truck
    :parameters (?d - driver ?t - truck ?l - location)
    :precondition (and (at ?t ?l) (driving ?d ?t))
    :effect (and (not (driving ?d ?t)) (at ?d ?l) (empty ?t)))

  (:action drive-truck
    :parameters (?t - truck ?from - location ?to - location ?d - driver)
    :precondition (and (at ?t ?from) (driving ?d ?t) (link ?from ?to))
    :effect (and (not (at ?t ?from)) (at ?t ?to)
                 (increase (driven) (time-to-drive ?from ?to))))

  (:action walk
    :parameters (?d - driver ?from - location ?to - location)
    :precondition (and (at ?d ?from) (path ?from ?to))
    :effect (and (not (at ?d ?from)) (at ?d ?to)
                 (increase (walked) (time-to-walk ?from ?to)))))
