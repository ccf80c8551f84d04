//! Which functions a pipeline's shader can run: its entry points' call graph in the composed
//! module, walked with the pipeline's override constants folded (and boolean arguments that
//! are constant at a call carried into the callee), so a branch the constants decide is
//! followed one way only. What a driver compiles out of a specialized pipeline is what this
//! leaves unreached.

use std::collections::BTreeSet;

use naga::{BinaryOperator, Block, Expression, Function, Handle, Literal, Module, Statement};
use pelt_preview::renderer::PipelineDesc;

/// The names of every function `desc`'s entry points can reach with its constants.
pub fn reached(desc: &PipelineDesc) -> BTreeSet<String> {
    let module = desc.shader.compose().unwrap_or_else(|e| panic!("{e}"));
    let (vs, fs) = desc.shader.entry_points();
    let mut walk = Walk {
        module: &module,
        desc,
        seen: BTreeSet::new(),
        names: BTreeSet::new(),
    };
    for e in module
        .entry_points
        .iter()
        .filter(|e| e.name == vs || e.name == fs)
    {
        let _ends = walk.block(&e.function, &e.function.body, &[]);
    }
    walk.names
}

/// Whether `names` holds item `item` of shared module `module` (as naga_oil decorates it),
/// or the pipeline's own function `item` (`module` empty).
pub fn holds(names: &BTreeSet<String>, module: &str, item: &str) -> bool {
    if module.is_empty() {
        return names.contains(item);
    }
    names.contains(&pelt_preview::shaders::decorated(module, item))
}

struct Walk<'m> {
    module: &'m Module,
    desc: &'m PipelineDesc,
    /// (function, its constant boolean arguments) already walked.
    seen: BTreeSet<(usize, Vec<Option<bool>>)>,
    names: BTreeSet<String>,
}

impl Walk<'_> {
    /// Walks `b`; whether it always ends the function (a return or discard on every path the
    /// constants leave), so the statements after it are never reached.
    fn block(&mut self, f: &Function, b: &Block, args: &[Option<bool>]) -> bool {
        for s in b.iter() {
            let ends = match s {
                Statement::Return { .. } | Statement::Kill => true,
                Statement::Block(b) => self.block(f, b, args),
                Statement::If {
                    condition,
                    accept,
                    reject,
                } => match self.value(f, *condition, args) {
                    Some(true) => self.block(f, accept, args),
                    Some(false) => self.block(f, reject, args),
                    None => {
                        let a = self.block(f, accept, args);
                        self.block(f, reject, args) && a
                    }
                },
                Statement::Switch { cases, .. } => {
                    for c in cases {
                        self.block(f, &c.body, args);
                    }
                    false
                }
                Statement::Loop {
                    body, continuing, ..
                } => {
                    self.block(f, body, args);
                    self.block(f, continuing, args);
                    false
                }
                Statement::Call {
                    function,
                    arguments,
                    ..
                } => {
                    let bound: Vec<Option<bool>> =
                        arguments.iter().map(|&a| self.value(f, a, args)).collect();
                    self.call(*function, bound);
                    false
                }
                _ => false,
            };
            if ends {
                return true;
            }
        }
        false
    }

    fn call(&mut self, h: Handle<Function>, args: Vec<Option<bool>>) {
        if !self.seen.insert((h.index(), args.clone())) {
            return;
        }
        let callee = &self.module.functions[h];
        if let Some(n) = &callee.name {
            self.names.insert(n.clone());
        }
        self.block(callee, &callee.body, &args);
    }

    /// The boolean value of `e` where the constants decide it.
    fn value(&self, f: &Function, e: Handle<Expression>, args: &[Option<bool>]) -> Option<bool> {
        match &f.expressions[e] {
            Expression::FunctionArgument(i) => args.get(*i as usize).copied().flatten(),
            other => self.fold(other, |h| self.value(f, h, args)),
        }
    }

    /// The value of a module-scope expression (a constant's or an override's default).
    fn global(&self, e: Handle<Expression>) -> Option<bool> {
        self.fold(&self.module.global_expressions[e], |h| self.global(h))
    }

    fn fold(
        &self,
        e: &Expression,
        sub: impl Fn(Handle<Expression>) -> Option<bool>,
    ) -> Option<bool> {
        match e {
            Expression::Literal(Literal::Bool(b)) => Some(*b),
            Expression::Constant(c) => self.global(self.module.constants[*c].init),
            Expression::Override(o) => {
                let o = &self.module.overrides[*o];
                let set = o.name.as_deref().and_then(|n| self.desc.constant(n));
                match set {
                    Some(v) => Some(v != 0.0),
                    None => o.init.and_then(|i| self.global(i)),
                }
            }
            Expression::Unary {
                op: naga::UnaryOperator::LogicalNot,
                expr,
            } => sub(*expr).map(|b| !b),
            Expression::Binary { op, left, right } => {
                let (l, r) = (sub(*left), sub(*right));
                match op {
                    BinaryOperator::LogicalAnd => match (l, r) {
                        (Some(false), _) | (_, Some(false)) => Some(false),
                        (Some(true), Some(true)) => Some(true),
                        _ => None,
                    },
                    BinaryOperator::LogicalOr => match (l, r) {
                        (Some(true), _) | (_, Some(true)) => Some(true),
                        (Some(false), Some(false)) => Some(false),
                        _ => None,
                    },
                    _ => None,
                }
            }
            _ => None,
        }
    }
}
