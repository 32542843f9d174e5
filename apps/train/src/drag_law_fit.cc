#include "hdvio/train/drag_law_fit.h"

#include "hdvio/core/error.h"
#include "hdvio/train/flight_loading.h"

namespace hdvio::train {

DragLaw fitDragLawOn(const std::vector<learned::FlightSamples>& flights, const DragTerms& terms,
                     const DragSigmaTerms& sigma_terms) {
  std::vector<Vec3> u, w, f;
  std::vector<double> thrust;
  for (const auto& fl : flights) {
    if (fl.force.size() != fl.size()) throw InputError(fl.name, 0, "drag law fit needs the flight's IMU");
    for (std::size_t k = 0; k < fl.size(); ++k) {
      u.push_back(fl.q_WB[k].conjugate() * fl.v_W[k]);
      w.push_back(fl.gyro[k]);
      thrust.push_back(fl.thrust[k].norm());
      f.push_back(fl.force[k] - fl.thrust[k]);
    }
  }
  if (u.size() < 100) throw InputError("", 0, "drag law fit needs at least 100 samples");
  return withFittedSigma(fitDragLaw(u, thrust, f, terms), u, w, thrust, f, sigma_terms);
}

std::vector<Vec3> lawSigma(const learned::FlightSamples& flight, const DragLaw& law) {
  std::vector<Vec3> out;
  out.reserve(flight.size());
  for (std::size_t k = 0; k < flight.size(); ++k)
    out.push_back(law.sigmaAt(flight.q_WB[k].conjugate() * flight.v_W[k], flight.gyro[k], flight.thrust[k].norm()));
  return out;
}

std::vector<Vec3> thrustPlusLaw(const learned::FlightSamples& flight, const DragLaw& law) {
  std::vector<Vec3> out;
  out.reserve(flight.size());
  for (std::size_t k = 0; k < flight.size(); ++k)
    out.push_back(flight.thrust[k] +
                  law.force(flight.q_WB[k].conjugate() * flight.v_W[k], flight.thrust[k].norm()));
  return out;
}

DragTerms parseDragTerms(const std::vector<std::string>& names, const std::string& file, const std::string& what) {
  DragTerms t{false, false, false, false};
  for (const std::string& term : names) {
    if (term == "linear") t.linear = true;
    else if (term == "rotor") t.rotor = true;
    else if (term == "quadratic") t.quadratic = true;
    else if (term == "lift") t.lift = true;
    else throw InputError(file, 0, what + ": unknown drag term '" + term + "' (linear, rotor, quadratic, lift)");
  }
  if (!t.linear && !t.rotor && !t.quadratic && !t.lift) throw InputError(file, 0, what + ": no drag term");
  return t;
}

DragSigmaTerms parseDragSigmaTerms(const std::vector<std::string>& names, const std::string& file,
                                   const std::string& what) {
  DragSigmaTerms t;
  for (const std::string& term : names) {
    if (term == "speed") t.speed = true;
    else if (term == "rate") t.rate = true;
    else if (term == "thrust") t.thrust = true;
    else if (term != "constant")
      throw InputError(file, 0, what + ": unknown sigma term '" + term + "' (constant, speed, rate, thrust)");
  }
  return t;
}

}  // namespace hdvio::train
