"""The particle-filter variants ``mcl``, ``lowvar``, ``amcl``, ``reset`` and ``maturing``.

One frame (CMU paper, Alg. 1): game-controller events (:mod:`cognition.localization.base`),
prediction with the odometry (CMU Alg. 2), the observation update in log space (sensor
models of :mod:`cognition.localization.sensor`), pose extraction (CMU III.E), then, if
anything was observed, resampling by the variant:

=========  ==================================================================================
variant    resampling step
=========  ==================================================================================
mcl        multinomial (DNT 4.1)
lowvar     low variance (DNT 4.6)
amcl       multinomial; a share max(0, 1 - w_fast / w_slow) of random poses (DNT 4.4), in
           mirrored pairs, or in the own half while the game state is INITIAL, READY or SET;
           w_slow and w_fast restart from 0 after an injection
reset      CMU Alg. 4: the same share comes from vision (two-post intersection, one-post circle,
           optionally a random feature, DNT 4.5), at least ``reset_probability`` while lost;
           the particle count adapts between ``min_particles`` and ``particles``: it grows as
           the per-observation evidence falls
maturing   low variance; candidate poses generated from single observations are tracked with
           the odometry and scored against later frames; only those consistent for
           ``maturing_threshold`` frames replace particles (Darmstadt VI,
           :mod:`cognition.localization.maturing`)
=========  ==================================================================================

A variant is a resampling draw and an injection strategy (:data:`VARIANT_STRATEGIES`), each in a
file named after its algorithm: :mod:`~cognition.localization.multinomial`,
:mod:`~cognition.localization.low_variance`, :mod:`~cognition.localization.amcl`,
:mod:`~cognition.localization.resetting` and :mod:`~cognition.localization.maturing`
(:mod:`cognition.localization.strategy` lists them); this module holds what every variant shares.
Vision poses come from :mod:`cognition.localization.resetting`. The compiled steps (motion
noise, resampling, injected poses and their slots, resetting) draw from the filter's own
xorshift64* state, seeded from its numpy Generator, which only draws the number of injections.
With a built-in strategy the frame's steps run in one compiled call (two when poses may be
injected: the Generator draws their number in between), :mod:`cognition.localization.frame_step`;
any other strategy runs them as Python calls (:meth:`ParticleFilter._update_by_steps`), and both
paths give the same numbers to the bit (``tests/test_frame_step.py``).

**Recovery** (what each variant does when it is wrong, e.g. after the robot was moved without
noticing, or after odometry that could not be trusted):

=========  ==========================================================================================
variant    recovery
=========  ==========================================================================================
mcl        none in the paper's algorithm: the particles only follow the odometry and the weights
lowvar     none in the paper's algorithm
amcl       random poses, as many as the drop of w_fast below w_slow says
reset      poses from vision, as many as the drop of w_fast below w_slow says; needs a goal post
           in view (or any feature with ``reset_from_any_feature``)
maturing   candidate poses from any feature, once they have been consistent for a while and
           explained the frames clearly better than the estimate (the latter not in the paper)
=========  ==========================================================================================

Safety net of every variant (not in the papers; ``relocalize_seconds`` > 0, the default). An
observation is *unexplained* when its mean likelihood under the particles, without the floors,
is below exp(``relocalize_log_likelihood``). When at least ``relocalize_share`` of the
observations of the last ``relocalize_seconds`` of game time were unexplained (at least 5
observed frames, spanning most of that time), the particles explain what the robot sees badly:
at the next resampling a share ``injection_max`` of them is replaced by random poses over the
field (mirrored pairs; the own half while the game state is INITIAL, READY or SET), as ``amcl``
does, and the window starts anew; this repeats while the observations stay unexplained. Three
choices keep the net from hurting a robot that is right but sees badly (the ``harsh``
false positives and occlusions leave up to half of a window unexplained now and then):

* a share of observations, not a run of bad frames: a wrong pose still explains a single line
  now and then, a right one misses a false positive;
* a share of the particles, each injected with the weight ``relocalize_weight`` relative to the
  others: it takes over only when it explains the next frames that much better than the cloud.
  Injected at full weight, poses that happened to explain one noisy frame took the estimate
  away (5 v 5 ``harsh`` recordings, maturing: mean error 0.216 m without the net, 0.36 m with
  full-weight injection, 0.228 m with 0.01);
* no pose near the estimate's mirror image, which explains every percept as well as the
  estimate does and would live on as a second mode (such poses are mirrored onto the estimate).

Measured on 8 recordings of a robot walking in its own half, carried to a random pose after
8 s (``default`` percepts): without the net ``mcl`` stayed lost for the remaining 62 s in
4 of 8, ``lowvar`` in 1 and ``maturing`` in 3; with it every variant found the robot again
(modulo the mirror symmetry) in every recording, at worst after 42 s.
:attr:`ParticleFilter.relocalizations` counts the injections; a study of the papers' plain
variants sets ``relocalize_seconds = 0``.

The field's mirror symmetry is not resolved by any variant: with goals of one colour (the
SPL fields) the percepts of a pose and of its mirror image (-x, -y, theta + pi) are the same,
so a robot moved without noticing may settle on either; with goals of different colours
(``kidsize``, or a colour scheme with distinct goals) the posts tell the two apart. Telling
them apart on an SPL field needs information from outside the robot's own percepts (the
game state before kickoff, teammates' ball), which this module does not use beyond the own
half of the game's setup phases. What the filters do keep is the side they are on: poses
from vision (``reset``, ``maturing``) that fall within :data:`~.frame_step.MIRROR_RADIUS` of the
estimate's mirror image, and nearer to it than to the estimate, are mirrored onto the estimate
before they replace particles (not in the papers). The distances count the heading
(:data:`~.frame_step.MIRROR_HEADING_SCALE`, 1 m per radian) as well as the position: near the
centre spot the estimate and its mirror image are close in position, and a guard by position
alone mirrored poses right beside the estimate across the field, or turned poses at the mirror
image's position facing the estimate's way into poses beside the estimate facing the other way,
which flipped robots at kickoff by 180 degrees for a minute or two. A few lines and one post fit
both halves equally, so such poses mature as readily as right ones; injected while the spread
test called an accurate robot lost, they flipped goalkeepers that then faced their own net, saw
nothing and stayed 180 degrees wrong (5 v 5 image matches; maturing, 60 s halves, seeds 0, 2, 3,
6: mean error 0.270, 0.152, 0.207, 0.192 m without, 0.080, 0.044, 0.162, 0.085 m with).

The evidence of a frame is the mean likelihood of the particles, taken per observation
(the K-th root for K observations) so that w_slow and w_fast do not jump with the number of
features in view. w_slow and w_fast follow the evidence without the likelihood floors (CMU's
0.9 for lines, NimbRo's confidence): the floors keep outliers from emptying the filter but
also hide a kidnapping (a wrong pose would still score at least the floor). The adaptive
particle count of ``reset`` follows the evidence with the floors. All weights live in log
space; after every update they are normalised, so an observation that no particle explains
leaves finite, uniform weights, never NaN.
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np
from numpy.typing import NDArray

from cognition.field import Field, FieldDimensions
from cognition.gamestate import GameStateId
from cognition.localization import kernels as K  # noqa: N812 - short kernel namespace
from cognition.localization.amcl import AMCLInjection
from cognition.localization.base import Localizer
from cognition.localization.fieldmodel import FieldModel
from cognition.localization.frame_step import (
    R_COUNT,
    R_OBSERVED,
    R_RELOCALIZE,
    R_UNEXPLAINED,
    away_from_mirror_nb,
    frame_step_nb,
    grow_ring,
    knobs,
    resample_step_nb,
    watch_nb,
)
from cognition.localization.kld import kld_count
from cognition.localization.low_variance import LOW_VARIANCE
from cognition.localization.maturing import Maturing
from cognition.localization.multinomial import MULTINOMIAL
from cognition.localization.params import LocalizationParams
from cognition.localization.places import placement_poses
from cognition.localization.resample import resample_nb
from cognition.localization.resetting import SensorResetting
from cognition.localization.sensor import N_O, NO_OBSERVATIONS, pack_observations, sensor_table
from cognition.localization.strategy import Injection, Resampling
from cognition.representations import RobotPose, SensorFrame

VARIANT_STRATEGIES: dict[str, tuple[Resampling, type[Injection]]] = {
    "mcl": (MULTINOMIAL, Injection),
    "lowvar": (LOW_VARIANCE, Injection),
    "amcl": (MULTINOMIAL, AMCLInjection),
    "reset": (MULTINOMIAL, SensorResetting),
    "maturing": (LOW_VARIANCE, Maturing),
}
"""Each variant's resampling draw and injection strategy (:mod:`cognition.localization.strategy`)."""
PARTICLE_VARIANTS = tuple(VARIANT_STRATEGIES)
_MODELS: OrderedDict[FieldDimensions, FieldModel] = OrderedDict()
_MODELS_KEPT = 8
"""Compiled maps kept (least recently used dropped): one per field geometry in use."""
_OWN_HALF_STATES = (GameStateId.INITIAL, GameStateId.READY, GameStateId.SET)
_NO_ROWS = np.zeros((0, 1))
_NO_OFFSETS = np.zeros(2, dtype=np.int64)
"""A percept table of no rows and its offsets, for a frame without percepts or with an empty
image. Writable, like the tables the simulator's percepts hold: :meth:`Percepts.empty
<cognition.percepts.Percepts.empty>` holds read-only ones, another numba type, for which the
compiled frame would be compiled a second time (about 30 s on a fresh machine)."""


def field_model(field: Field) -> FieldModel:
    """The compiled map of ``field``, shared by every filter on a field of the same geometry.

    The cache is keyed by the field's dimensions (every match builds its own ``Field`` of the
    same preset) and holds at most :data:`_MODELS_KEPT` maps, so that building matches over
    and over (environment resets) reuses one map instead of adding one per match.
    """
    model = _MODELS.get(field.dims)
    if model is None:
        model = FieldModel(field)
        _MODELS[field.dims] = model
        while len(_MODELS) > _MODELS_KEPT:
            _MODELS.popitem(last=False)
    else:
        _MODELS.move_to_end(field.dims)
    return model


class ParticleFilter(Localizer):
    """Monte Carlo localization; ``variant`` picks the resampling draw and the injection
    strategy (module docstring, :data:`VARIANT_STRATEGIES`).

    ``resampling`` and ``injection`` replace the variant's own strategies, so that other
    combinations can be studied (for example the low-variance draw with AMCL's random poses);
    the filter's :attr:`name` then says which, ``"<variant>:<draw>+<injection>"``."""

    def __init__(
        self,
        variant: str,
        field: Field,
        params: LocalizationParams | None = None,
        rng: np.random.Generator | None = None,
        player_number: int = 1,
        players_per_team: int = 5,
        *,
        resampling: Resampling | None = None,
        injection: type[Injection] | None = None,
    ):
        if variant not in VARIANT_STRATEGIES:
            raise ValueError(f"unknown particle-filter variant {variant!r}; valid: {list(PARTICLE_VARIANTS)}")
        own_resampling, own_injection = VARIANT_STRATEGIES[variant]
        resampling = own_resampling if resampling is None else resampling
        injection = own_injection if injection is None else injection
        if not isinstance(resampling, Resampling):
            raise TypeError(f"resampling must be a Resampling (multinomial.MULTINOMIAL, ...), got {resampling!r}")
        if not (isinstance(injection, type) and issubclass(injection, Injection)):
            raise TypeError(f"injection must be an Injection subclass (amcl.AMCLInjection, ...), got {injection!r}")
        same = resampling == own_resampling and injection is own_injection
        self.name = variant if same else f"{variant}:{resampling.name}+{injection.name}"
        super().__init__(field, params, rng, player_number, players_per_team)
        p = self.params
        self.resampling: Resampling = resampling
        """The resampling draw (:mod:`.multinomial` or :mod:`.low_variance`)."""
        self.injection: Injection = injection(p)
        """The injection strategy (what replaces particles after resampling)."""
        self.model = field_model(field)
        self.kernel_state = np.array([int(self.rng.integers(1, 2**63 - 1))], dtype=np.uint64)
        """The xorshift64* state every compiled step of this filter draws from."""
        cap = p.particles
        self.parts = np.zeros((cap, 3))
        self._spare = np.zeros((cap, 3))
        self.logw = np.zeros(cap)
        self.w = np.full(cap, 1.0 / cap)
        self.ll_buffer = np.zeros(cap)
        """Log-likelihood work space of the compiled sensor update (one entry per particle)."""
        self.scratch = np.zeros((6, cap))
        """Work space of the compiled sensor update (:func:`kernels.log_likelihood_nb`)."""
        self._pose_out = np.zeros(14)
        self._cov = self._pose_out[5:14].reshape(3, 3)
        """The pose's covariance (a view of ``_pose_out``, written by :func:`kernels.frame_nb`)."""
        self._pose_par = np.array([p.cluster_radius, 0.5, 0.5, p.jump_weight, math.exp(p.relocalize_log_likelihood)])
        self._prev = np.zeros(4)
        self._motion = np.array([p.sigma_mx, p.sigma_mtheta, p.sigma_mytheta, p.motion_floor_xy, p.motion_floor_theta])
        self.hough_params = np.array(
            [
                1.0 if p.line_model == "hough" else 0.0,
                p.hough_sigma_rho,
                p.hough_sigma_theta,
                p.hough_sigma_u,
                p.hough_sigma_spread,
            ]
        )
        """The line model of the compiled sensor update: 1 for NimbRo's Hough model, then its sigmas."""
        self._table = sensor_table(p)
        m = self.model
        grid = m.partial_grid if p.partial_crossings > 0.0 else m.cross_grid
        self.maps = (m.posts, m.crossings, m.lines, m.marks, m.poles, grid, m.line_grid, m.geo)
        """The map arrays of :attr:`model`, in the order the kernels take them (the crossing grid
        of the parameters' ``partial_crossings``)."""
        self._slots = np.zeros(cap, dtype=np.int64)
        """Slots of the poses injected at a resampling (:func:`resample.resample_nb`)."""
        self.n = self.injection.initial_count()
        self.injected = 0
        """Particles replaced by random or vision poses in the latest update."""
        self._last_resample = np.array([-1e9])
        """Time (s) of the latest resampling (an array: the compiled frame updates it)."""
        self._own_half = True
        self._watched = (np.zeros(64), np.zeros(64, dtype=np.int64), np.zeros(64, dtype=np.int64))
        """(time, unexplained observations, observations) of the observed frames in the safety
        net's window: a ring buffer (:func:`~.frame_step.watch_nb`) with :attr:`_watch_state` its state."""
        self._watch_state = np.zeros(5, dtype=np.int64)
        self._knobs = knobs(self.injection, p, resampling.low_variance, field.half_length, field.half_width)
        """The compiled frame's numbers for a built-in strategy (:mod:`.frame_step`); ``None``:
        the strategy is another class and the frame runs its Python steps."""
        inj = self.injection
        if isinstance(inj, Maturing):
            self._candidates = (inj.cand, inj.ages, inj.advantage, inj.in_use)
        else:
            none = (np.zeros((0, 3)), np.zeros(0, dtype=np.int64), np.zeros((0, 2)), np.zeros(1, dtype=np.int64))
            self._candidates = none
        self.relocalizations = 0
        """Times the safety net injected random poses (module docstring)."""
        self.observation_evidence = np.zeros(0)
        """Each observation's mean likelihood under the particles in the latest frame (no floors)."""
        n0 = placement_poses(field, self.player_number, self.players_per_team, GameStateId.INITIAL, False)
        self.set_particles_around(n0)

    @property
    def estimate(self) -> NDArray[np.float64]:
        """This frame's pose estimate (x m, y m, theta rad; team frame) once the observation update
        has run: a view of the compiled frame's output, against which the maturing candidates are scored."""
        return self._pose_out[:3]

    @property
    def w_slow(self) -> float:
        """Slow average of the per-observation evidence (DNT 4.4; 0 for the variants without injection)."""
        return self.injection.w_slow

    @property
    def w_fast(self) -> float:
        """Fast average of the per-observation evidence (DNT 4.4)."""
        return self.injection.w_fast

    # -- initial beliefs -------------------------------------------------------------------
    def set_particles_around(self, centres: NDArray[np.float64], sigma_xy: float | None = None) -> None:
        """Spread all particles around the poses ``centres`` (K x 3, team frame), in turn."""
        p = self.params
        sxy = p.placement_sigma_xy if sigma_xy is None else sigma_xy
        centres = np.ascontiguousarray(np.asarray(centres, dtype=np.float64).reshape(-1, 3))
        K.gaussian_set_nb(self.parts, 0, self.n, centres, sxy, p.placement_sigma_theta, self.kernel_state)
        self.logw[: self.n] = 0.0
        self.w[: self.n] = 1.0 / self.n
        self._prev[3] = 0.0

    def set_uniform(self, own_half: bool = False) -> None:
        """Spread all particles uniformly over the field (or the own half), all headings."""
        hl, hw = self.field.half_length, self.field.half_width
        K.uniform_set_nb(self.parts, 0, self.n, hl, hw, own_half, self.kernel_state)
        self.logw[: self.n] = 0.0
        self.w[: self.n] = 1.0 / self.n
        self._prev[3] = 0.0

    # -- game-controller events ------------------------------------------------------------
    def on_side_switch(self) -> None:
        n = self.n
        self.parts[:n, :2] *= -1.0
        self.parts[:n, 2] = np.mod(self.parts[:n, 2] + 2.0 * math.pi, 2.0 * math.pi) - math.pi
        self.injection.side_switch()
        self._prev[3] = 0.0

    def on_placement(self, poses: NDArray[np.float64]) -> None:
        self.set_particles_around(poses)
        self._forget()

    def on_penalty(self, penalized: bool, state: int) -> None:
        if self.params.penalty_prior:
            self.set_particles_around(self.return_poses())
            self._forget()

    def repair(self, frame: SensorFrame) -> None:
        self.n = self.params.particles
        if frame.game.state == GameStateId.INITIAL:
            n0 = placement_poses(self.field, self.player_number, self.players_per_team, GameStateId.INITIAL, False)
            self.set_particles_around(n0)
        else:
            self.set_uniform(own_half=frame.game.state in _OWN_HALF_STATES)
        self._forget()

    def _forget(self) -> None:
        """Drop what the filter learnt about its own health and its candidates (new beliefs)."""
        self.injection.forget()
        self._watch_state[:] = 0

    @property
    def unexplained_share(self) -> float:
        """Share of the observations in the safety net's window that were unexplained (0..1)."""
        observed = int(self._watch_state[R_OBSERVED])
        return int(self._watch_state[R_UNEXPLAINED]) / observed if observed else 0.0

    def _watch(self, time: float, unexplained: int, observed: int) -> None:
        """The safety net (module docstring): ask for random poses at the next resampling when most
        recent observations were unexplained (:func:`~.frame_step.watch_nb`)."""
        self._watched = grow_ring(*self._watched, self._watch_state)
        p = self.params
        window, share = p.relocalize_seconds, p.relocalize_share
        watch_nb(time, unexplained, observed, window, share, *self._watched, self._watch_state)

    @property
    def _relocalize(self) -> bool:
        """Whether the safety net asks for random poses at the next resampling."""
        return bool(self._watch_state[R_RELOCALIZE])

    @_relocalize.setter
    def _relocalize(self, value: bool) -> None:
        self._watch_state[R_RELOCALIZE] = 1 if value else 0

    # -- the frame -------------------------------------------------------------------------
    def _update(self, frame: SensorFrame, truth: tuple[float, float, float] | None) -> RobotPose:
        self._own_half = frame.game.state in _OWN_HALF_STATES
        if self._knobs is None:
            return self._update_by_steps(frame)
        # a built-in strategy: the steps of _update_by_steps in one or two compiled calls (.frame_step)
        p = self.params
        n = self.n
        o = frame.odometry
        percepts = frame.percepts
        rows, offsets = (_NO_ROWS, _NO_OFFSETS) if percepts is None else percepts.table_and_offsets
        n_rows = offsets[-1] - offsets[0]
        if n_rows == 0:
            rows, offsets = _NO_ROWS, _NO_OFFSETS
        explained, packed, weights = np.empty(n_rows), np.empty((n_rows, N_O)), np.empty(n)
        if self._watch_state[R_COUNT] >= self._watched[0].shape[0]:  # the ring is full: grow it
            self._watched = grow_ring(*self._watched, self._watch_state)
        cand, ages, advantage, in_use = self._candidates
        parts, spare, averages = self.parts, self._spare, self.injection.averages
        x, y, th, spread, k, share, n_new, relocalize = frame_step_nb(
            parts, spare, n, self.logw, self.w, weights, self.ll_buffer, self.scratch, self._prev, self._pose_par,
            self._pose_out, explained, self._motion, self.kernel_state, self.hough_params, *self.maps, rows, offsets,
            self._table, packed, bool(frame.picked_up or self._penalty), o.dx, o.dy, o.dtheta, frame.time,
            self._own_half, self._knobs, self._last_resample, *self._watched, self._watch_state, averages, cand, ages,
            advantage, in_use, self._slots,
        )  # fmt: skip
        pose = RobotPose(x, y, th, self._cov.copy(), spread > p.lost_spread, n, parts[:n].copy(), weights, self.name)
        self.observation_evidence = explained[:k]
        self.injected = 0
        if share > 0.0:  # the number of poses to inject comes from the numpy Generator, as in _resample
            m_inj = int(self.rng.binomial(n_new, share))
            posts, crossings, _, marks, poles = self.maps[:5]
            self.injected, relocalize = resample_step_nb(
                parts, n, self.w, self.logw, spare, n_new, m_inj, self._slots, self.kernel_state, self._knobs,
                packed[:k], x, y, th, self._own_half, posts, crossings, marks, poles, self.maps[7], self._watch_state,
                averages, cand, ages, advantage, in_use,
            )  # fmt: skip
        if share >= 0.0:  # resampled: the new set is in the spare buffer
            self.parts, self._spare = spare, parts
            self.n = n_new
        if relocalize:
            self._relocalize_now(pose)
        return pose

    def _update_by_steps(self, frame: SensorFrame) -> RobotPose:
        """The frame as Python steps around the kernels, calling the strategy's methods (any
        :class:`~.strategy.Injection`; :mod:`.frame_step` runs the built-in ones in one call)."""
        p = self.params
        n = self.n
        o = frame.odometry
        blind = frame.picked_up or self._penalty  # the base class tracked this frame's penalty
        obs = NO_OBSERVATIONS if blind else pack_observations(frame.percepts, self._table)
        k = obs.shape[0]
        explained = np.empty(k)
        evidence, raw_evidence, x, y, th, spread, unexplained = K.frame_nb(
            self.parts, n, o.dx, o.dy, o.dtheta, self._motion, self.kernel_state, obs, self.hough_params, *self.maps,
            self.ll_buffer, self.scratch, self.logw, self.w, self._prev, self._pose_par, self._pose_out, explained,
        )  # fmt: skip
        self.injection.observe(self, obs, o.dx, o.dy, o.dtheta)
        lost = spread > p.lost_spread
        pose = RobotPose(
            x, y, th, self._cov.copy(), lost, n, self.parts[:n].copy(), self.w[:n].copy(), self.name
        )  # fmt: skip
        self.injected = 0
        self.observation_evidence = explained
        if k:
            self._watch(frame.time, unexplained, k)
        if k and frame.time - self._last_resample[0] >= p.resample_interval:
            self._last_resample[0] = frame.time
            self._resample(obs, math.exp(evidence / k), math.exp(raw_evidence / k), lost, pose)
            if self._relocalize:
                self._relocalize = False
                self._relocalize_now(pose)
        return pose

    def _relocalize_now(self, pose: RobotPose) -> None:
        """The safety net: random poses in place of particles just resampled."""
        p = self.params
        self.relocalizations += 1
        m = max(1, round(p.injection_max * self.n))
        slots = K.choose_nb(self.n, m, self.kernel_state)
        self.parts[slots] = self.away_from_mirror(self.uniform_poses(m), pose)
        self.logw[slots] = math.log(p.relocalize_weight)  # must explain the next frames far better
        self.w[: self.n] = np.exp(self.logw[: self.n])
        self.w[: self.n] /= self.w[: self.n].sum()
        self.injected += m

    # -- resampling by the variant's strategies -----------------------------------------------
    def _resample(self, obs: NDArray[np.float64], w_avg: float, w_raw: float, lost: bool, pose: RobotPose) -> None:
        """Resample with the variant's draw and inject its strategy's fresh poses, if any.

        The injection strategy sets the particle count (``reset``: adaptive) and the share to
        replace; the number of injections is drawn from the numpy Generator before the
        compiled resampling runs: the two random streams are independent, so the order
        between them does not matter, and one compiled call resamples, resets the weights and
        chooses the slots. Poses from vision (``reset``, ``maturing``) that lie near the
        mirror image of ``pose``, the estimate of this frame, are mirrored onto it first
        (:meth:`away_from_mirror`)."""
        p = self.params
        inj = self.injection
        n_old = self.n
        n_new = inj.count(n_old, w_avg)
        share = inj.share(w_raw, lost)
        if p.kld:  # KLD while tracking; a search (lost, injecting, the safety net) gets every particle
            if lost or share > 0.0 or self._relocalize:
                n_new = p.particles
            else:
                lo = min(p.kld_min_particles, p.particles)
                n_new = kld_count(
                    self.parts, self.w, n_old, lo, p.particles, p.kld_epsilon, p.kld_z, p.kld_bin_xy, p.kld_bin_theta
                )
        m_inj = int(self.rng.binomial(n_new, share)) if share > 0.0 else 0
        resample_nb(
            self.parts, n_old, self.w, self.logw, self._spare, n_new, self.resampling.low_variance,
            p.resample_jitter_xy, p.resample_jitter_theta, m_inj, self._slots, self.kernel_state,
        )  # fmt: skip
        self.parts, self._spare = self._spare, self.parts
        self.n = n_new
        if m_inj == 0:
            return
        got = inj.inject(self, self._slots[:m_inj], obs, pose)
        if got == 0:
            return
        self.injected = got
        inj.restart()

    @staticmethod
    def away_from_mirror(fresh: NDArray[np.float64], pose: RobotPose) -> NDArray[np.float64]:
        """``fresh`` with every pose within :data:`~.frame_step.MIRROR_RADIUS` of the estimate's mirror image
        replaced by its own mirror image (which lies near the estimate). The mirror image
        explains the percepts exactly as well as the estimate: seeded there, a second mode would
        live on and could take the estimate across the field."""
        fresh = np.ascontiguousarray(fresh, dtype=np.float64)
        away_from_mirror_nb(fresh, np.arange(fresh.shape[0]), pose.x, pose.y, pose.theta)  # the compiled frame's rule
        return fresh

    def uniform_poses(self, m: int) -> NDArray[np.float64]:
        """``m`` random poses over the field (mirrored pairs), or the own half in the setup states."""
        fresh = np.empty((m, 3))
        K.uniform_set_nb(fresh, 0, m, self.field.half_length, self.field.half_width, self._own_half, self.kernel_state)
        return fresh

    # -- maturing candidates (Darmstadt VI, :mod:`cognition.localization.maturing`) -------------
    @property
    def candidates(self) -> NDArray[np.float64]:
        """Maturing candidate poses (C x 3; none for the other variants) and, in
        :attr:`candidate_counts`, their ages."""
        inj = self.injection
        return inj.cand[: inj.nc].copy() if isinstance(inj, Maturing) else np.zeros((0, 3))

    @property
    def candidate_counts(self) -> NDArray[np.int64]:
        inj = self.injection
        return inj.ages[: inj.nc].copy() if isinstance(inj, Maturing) else np.zeros(0, dtype=np.int64)
