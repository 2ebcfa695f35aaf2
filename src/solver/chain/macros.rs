//! The macros a mechanism with a compliant chain uses: [`crate::chain_variables!`] (its
//! variables of the elastodynamic level, inside [`crate::model_variables!`]) and
//! [`crate::chain_hooks!`] (its `impl Dynamics` items from the functions of [`super`]; all of
//! them and the states by [`crate::chain_dynamics!`]).

/// The variables of the elastodynamic level every integrating model declares the same way,
/// written once: used inside [`crate::model_variables!`] as `@with crate::chain_variables { .. }`.
///
/// - `solver(STAGE)`: `solver.method`, `solver.rtol`, `solver.atol`, `solver.max_step`
///   (parameters feeding the stage); `solver()`: feeding everything (a model without stages);
/// - `results(STAGE)`: `elastic.E_residual` and `solver.steps` (outputs needing the stage);
///   `steps` alone: `solver.steps` of a model without stages;
/// - `states(STAGE; x = ("elastic.x", "m", "State: ...") => der_x "m/s", ...)`: the continuous
///   states (locals needing the stage) and then their derivatives `der(<name>)`, in order;
/// - `states(STAGE, length; "x ...", "xd ...", "W ...")`: the states `y = [x, ẋ, W]` of a chain
///   whose coordinate is a length (`elastic.x` m, `elastic.xd` m/s, `elastic.W` J), described;
///   `states(STAGE, angle; ..)`: of one whose coordinate is an angle (`elastic.q` rad,
///   `elastic.qd` rad/s, `elastic.W` J);
/// - `spring(STAGE; k, "k ...", "zeta ...")`: `elastic.k` (default `k`) and `elastic.zeta` of a
///   chain that is a spring-damper ([`crate::solver::vars::stiffness`],
///   [`crate::solver::vars::damping_ratio`]), described, feeding the stage.
/// - `contact(STAGE; "Times the roller ...", "... force ...", "scope")`: `contact.liftoffs` (the
///   roller's contact-opening events, counted) and `contact.F_impact` (the largest force after a
///   landing, taken at the accepted steps) of a chain whose roller can lift off, needing the
///   stage; the count's opening, the force's subject and the scope in brackets described.
#[macro_export]
macro_rules! chain_variables {
    (@callback $head:tt $done:tt { states($s:expr, $coordinate:ident; $x:literal, $xd:literal, $w:literal $(,)?) } $( $rest:tt )*) => {
        $crate::chain_variables!(@$coordinate (@states $head $done $s, $x $xd $w) $( $rest )*);
    };
    // the names and units of a chain's coordinate and its rate, and of their derivatives
    (@length ($( $then:tt )*) $( $rest:tt )*) => {
        $crate::chain_variables!($( $then )* [elastic_x "elastic.x" "m" der_elastic_x "m/s", elastic_xd "elastic.xd" "m/s" der_elastic_xd "m/s2"] $( $rest )*);
    };
    (@angle ($( $then:tt )*) $( $rest:tt )*) => {
        $crate::chain_variables!($( $then )* [elastic_q "elastic.q" "rad" der_elastic_q "rad/s", elastic_qd "elastic.qd" "rad/s" der_elastic_qd "rad/s2"] $( $rest )*);
    };
    (@states $head:tt $done:tt $s:expr, $x:literal $xd:literal $w:literal [$x_id:ident $x_name:literal $x_unit:literal $dx_id:ident $dx_unit:literal, $xd_id:ident $xd_name:literal $xd_unit:literal $dxd_id:ident $dxd_unit:literal] $( $rest:tt )*) => {
        $crate::chain_variables!(@callback $head $done { states($s;
            $x_id = ($x_name, $x_unit, $x) => $dx_id $dx_unit,
            $xd_id = ($xd_name, $xd_unit, $xd) => $dxd_id $dxd_unit,
            elastic_W = ("elastic.W", "J", $w) => der_elastic_W "W",
        ) } $( $rest )*);
    };
    (@callback $head:tt [ $( $done:tt )* ] { spring($s:expr; $k:expr, $dk:literal, $dz:literal $(,)?) } $( $rest:tt )*) => {
        $crate::model_variables!(@munch $head [ $( $done )*
            (elastic_k = $crate::solver::vars::stiffness($k, $dk).feeds($s))
            (elastic_zeta = $crate::solver::vars::damping_ratio($dz).feeds($s))
        ] $( $rest )*);
    };
    (@callback $head:tt [ $( $done:tt )* ] { contact($s:expr; $liftoffs:literal, $impact:literal, $scope:literal $(,)?) } $( $rest:tt )*) => {
        $crate::model_variables!(@munch $head [ $( $done )*
            (contact_liftoffs = $crate::model::Var::int_output("contact.liftoffs", concat!($liftoffs, ": contact-opening events, located by the FMU's integrator in Co-Simulation, by the host in Model Exchange (", $scope, ")")).needs($s).event())
            (contact_F_impact = $crate::model::Var::output("contact.F_impact", "N", concat!("Largest ", $impact, ", taken ", $crate::at_accepted_steps!(), " (", $scope, ")")).needs($s))
        ] $( $rest )*);
    };
    (@callback $head:tt [ $( $done:tt )* ] { solver($( $s:expr )?) } $( $rest:tt )*) => {
        $crate::model_variables!(@munch $head [ $( $done )*
            (solver_method = $crate::solver::vars::method() $( .feeds($s) )?)
            (solver_rtol = $crate::solver::vars::rtol() $( .feeds($s) )?)
            (solver_atol = $crate::solver::vars::atol() $( .feeds($s) )?)
            (solver_max_step = $crate::solver::vars::max_step() $( .feeds($s) )?)
        ] $( $rest )*);
    };
    (@callback $head:tt [ $( $done:tt )* ] { results($s:expr) } $( $rest:tt )*) => {
        $crate::model_variables!(@munch $head [ $( $done )*
            (elastic_E_residual = $crate::solver::vars::e_residual().needs($s))
            (solver_steps = $crate::solver::vars::steps().needs($s))
        ] $( $rest )*);
    };
    (@callback $head:tt [ $( $done:tt )* ] { steps } $( $rest:tt )*) => {
        $crate::model_variables!(@munch $head [ $( $done )*
            (solver_steps = $crate::solver::vars::steps())
        ] $( $rest )*);
    };
    (@callback $head:tt [ $( $done:tt )* ] { states($s:expr; $( $x:ident = ($name:literal, $unit:literal, $desc:literal) => $dx:ident $dunit:literal ),+ $(,)?) } $( $rest:tt )*) => {
        $crate::model_variables!(@munch $head [ $( $done )*
            $( ($x = $crate::model::Var::local($name, $unit, $desc).needs($s)) )+
            $( ($dx = $crate::model::Var::local(concat!("der(", $name, ")"), $dunit, concat!("Derivative of ", $name)).derivative_of(Self::$x as u32).needs($s)) )+
        ] $( $rest )*);
    };
}

/// The hooks of [`crate::model::Model`] of a model whose elastodynamic level is the
/// `Option<Chain<_>>` in field `$chain`, its ODE's physics in field `$physics`: each hook named
/// becomes the one-line call of this module's function of that name. Used inside `impl Model`:
///
/// ```text
/// crate::chain_hooks!(dynamic, params: do_step, me_states, me_set_states, me_derivatives,
///     me_event_indicators, me_event, me_completed_step, save_state, restore_state);
/// ```
///
/// A hook not named keeps the model's own implementation (or the trait's default).
#[macro_export]
macro_rules! chain_hooks {
    ($chain:ident, $physics:ident: $($hook:ident),+ $(,)?) => {
        $($crate::chain_hooks!(@$hook $chain $physics);)+
    };
    (@do_step $chain:ident $physics:ident) => {
        fn do_step(
            &mut self,
            v: &mut $crate::model::Values<<Self as $crate::model::Model>::Var>,
            time: f64,
            h: f64,
            log: &mut dyn $crate::model::Log,
        ) -> $crate::model::Outcome {
            $crate::solver::chain::do_step(self.$chain.as_mut(), &self.$physics, v, time, h, log)
        }
    };
    (@me_states $chain:ident $physics:ident) => {
        $crate::chain_hooks!(@forward $chain $physics me_states(x: &mut [f64]) else x.fill(0.0));
    };
    (@me_set_states $chain:ident $physics:ident) => {
        $crate::chain_hooks!(@forward $chain $physics me_set_states(x: &[f64]) else ());
    };
    (@me_derivatives $chain:ident $physics:ident) => {
        $crate::chain_hooks!(@forward $chain $physics me_derivatives(dx: &mut [f64]) else dx.fill(0.0));
    };
    (@me_event_indicators $chain:ident $physics:ident) => {
        $crate::chain_hooks!(@forward $chain $physics me_event_indicators(z: &mut [f64]) else z.fill(1.0));
    };
    (@me_event $chain:ident $physics:ident) => {
        $crate::chain_hooks!(@forward $chain $physics me_event(log: &mut dyn $crate::model::Log) else ());
    };
    (@me_completed_step $chain:ident $physics:ident) => {
        $crate::chain_hooks!(@forward $chain $physics me_completed_step(log: &mut dyn $crate::model::Log) else ());
    };
    // a Model Exchange hook `name(v, time, arg)` is `MeCall::name(arg)` on the chain; without
    // one (below the elastodynamic level) the expression after `else`
    (@forward $chain:ident $physics:ident $name:ident($arg:ident: $ty:ty) else $absent:expr) => {
        fn $name(&mut self, v: &$crate::model::Values<<Self as $crate::model::Model>::Var>, time: f64, $arg: $ty) {
            match $crate::solver::chain::MeCall::of(self.$chain.as_mut(), &self.$physics, v, time) {
                Some(call) => call.$name($arg),
                None => $absent,
            }
        }
    };
    (@save_state $chain:ident $physics:ident) => {
        fn save_state(&self) -> Vec<f64> {
            $crate::solver::chain::save_state(self.$chain.as_ref())
        }
    };
    (@restore_state $chain:ident $physics:ident) => {
        fn restore_state(&mut self, s: &[f64]) -> Result<(), String> {
            $crate::solver::chain::restore_state(self.$chain.as_mut(), s)
        }
    };
}

/// The `impl Dynamics` of the model `$model` whose only internal state is the `Option<Chain<_>>`
/// in field `$chain`, its ODE's physics in field `$physics`: the three states `y = [x, ẋ, W]`,
/// `$n` event indicators (documented by the attributes before them) and every hook by
/// [`crate::chain_hooks!`] (Co-Simulation, Model Exchange and the FMU state from
/// [`crate::solver::chain`]); with [`crate::chain_access!`].
#[macro_export]
macro_rules! chain_dynamics {
    ($model:ty, $chain:ident, $physics:ident, $(#[$doc:meta])* EVENT_INDICATORS = $n:expr $(,)?) => {
        $crate::chain_access!($model, $chain, $physics);

        impl $crate::model::Dynamics<<$model as $crate::model::Model>::Var> for $model {
            const STATES: usize = 3;
            $(#[$doc])*
            const EVENT_INDICATORS: usize = $n;

            $crate::chain_hooks!($chain, $physics: do_step, me_states, me_set_states,
                me_derivatives, me_event_indicators, me_event, me_completed_step, save_state,
                restore_state);
        }
    };
}

/// [`crate::solver::chain::ChainAccess`] for the model `$model` whose chain is the
/// `Option<Chain<_>>` in field `$chain`, its ODE's physics in field `$physics`.
#[macro_export]
macro_rules! chain_access {
    ($model:ty, $chain:ident, $physics:ident) => {
        impl $crate::solver::chain::ChainAccess for $model {
            type Var = <$model as $crate::model::Model>::Var;
            fn with_chain_ode(
                &mut self,
                v: &$crate::model::Values<Self::Var>,
                time: f64,
                f: &mut dyn FnMut(&dyn $crate::solver::OdeSystem, [f64; 3]),
            ) -> bool {
                let call = $crate::solver::chain::MeCall::of(
                    self.$chain.as_mut(),
                    &self.$physics,
                    v,
                    time,
                );
                call.map(|c| c.with_chain_ode(f)).is_some()
            }
        }
    };
}

/// Inside `impl OdeSystem for` a chain's ODE: its dimension (3), the right-hand side of
/// `y = [x, ẋ, W]` ([`crate::solver::chain::ChainOde`]): `ẋ`, then the acceleration and the
/// power the expressions after `=>` read off the chain's point `pt` at `(t, y)`
/// ([`crate::solver::chain::ChainOde::point_kept`]), the error norm without `W` (a work kept
/// for the energy balance), and `ẋ`'s absolute tolerance no finer than the arithmetic resolves
/// ([`crate::solver::chain::rate_tolerance`]). With `via f:` first, the point is `f(self, t, y)`
/// instead (a chain whose right-hand side needs less than its point, e.g. `via Self::eval_kept:`).
#[macro_export]
macro_rules! chain_rhs {
    ($pt:ident => $xdd:expr, $power:expr) => {
        $crate::chain_rhs!(via $crate::solver::chain::ChainOde::point_kept: $pt => $xdd, $power);
    };
    (via $get:path: $pt:ident => $xdd:expr, $power:expr) => {
        fn dim(&self) -> usize {
            3
        }
        fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
            let $pt = $get(self, t, y);
            dy[0] = y[1];
            dy[1] = $xdd;
            dy[2] = $power;
        }
        fn error_weight(&self, i: usize) -> f64 {
            if i == 2 { 0.0 } else { 1.0 }
        }
        fn abs_tol(&self, i: usize, atol: f64, y: &[f64]) -> f64 {
            $crate::solver::chain::rate_tolerance(self, i, atol, y)
        }
    };
}
