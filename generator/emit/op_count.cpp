#include "emit/op_count.hpp"

namespace sweepgen::emit {

void OpCount::count(symbolic::Op op) {
  using symbolic::Op;
  switch (op) {
    case Op::add:
    case Op::sub: ++add; break;
    case Op::mul: ++mul; break;
    case Op::div:
    case Op::sqrt: ++div; break;
    case Op::neg: ++neg; break;
    case Op::sin:
    case Op::cos:
    case Op::atan2: ++trig; break;
    case Op::abs:
    case Op::equilibration_scale:
    case Op::min:
    case Op::max:
    case Op::select_greater:
    case Op::select_path: ++compare; break;
    case Op::constant:
    case Op::input: break;
  }
}

OpCount& OpCount::operator+=(const OpCount& o) {
  add += o.add;
  mul += o.mul;
  div += o.div;
  neg += o.neg;
  trig += o.trig;
  compare += o.compare;
  return *this;
}

std::string OpCount::summary() const {
  return "add " + std::to_string(add) + ", mul " + std::to_string(mul) + ", div " + std::to_string(div) + ", neg " +
         std::to_string(neg) + ", sin/cos " + std::to_string(trig) + ", compare " + std::to_string(compare) +
         " (total " + std::to_string(total()) + ")";
}

}  // namespace sweepgen::emit
