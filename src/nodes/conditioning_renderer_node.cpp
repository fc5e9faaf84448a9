// Standalone node running the multimodal_nvs/ConditioningRenderer nodelet class in its own
// process, with the node's name, namespace, remappings and private parameters.
#include "standalone_nodelet.hpp"

int main(int argc, char** argv) {
  return multimodal_nvs::runStandaloneNodelet(argc, argv, "conditioning_renderer",
                                              "multimodal_nvs/ConditioningRenderer");
}
