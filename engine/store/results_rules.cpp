#include "engine/store/results_rules.hpp"

#include <algorithm>
#include <array>

namespace ggk::engine {

namespace {

// The commits from 10a1054 (common random numbers) up to the one that records
// `rules`: their files are rules 2 without the attribute. Sorted; full hashes
// (`git rev-list 10a1054^..<that commit>`), matched by the file's abbreviation.
constexpr std::array<std::string_view, 108> kUnmarkedRules2 = {
    "00bd24771d7d9bc92fb90d5816460a348a78e400", "0107d593ee29818c5f07e9465b9c6c92214c81a3",
    "02526cc7807f505a59cee8b8f6b00785c94556c2", "02a552d92619bc70714c2a3e5e10871a454edbef",
    "044dc54fc04cece9fe8d00a1a4af18c69eefa493", "064302868a8aed7a8271b1e77bee6febfcc6bf04",
    "0ad3a95ef1ceee0c452d40940cbb1bc0a2f2da74", "106fd578f6f2e13a94ae097e8050b224ca81f607",
    "10a10540265a53ee7e81c4675b7d5b4f1d1e8f83", "11cdf89413bf2dd85f386def9d76b28feb18682e",
    "11fdb3011cbddb4290cf764cf0bde19be7150dc6", "127d6843597ae0af1e7ebce3f5241e49da390513",
    "131db444b6a1f46c1cff7555d68876afc9832588", "13f057ca2710d1cf56961718515094dcacb21402",
    "159e50b20ff17d1534fc325abd2b8f070672f1a4", "1807a20619bcb4bd61ac36ab2923dab6296dd7b3",
    "18d4d8735a613cc54591a399f936f8ee74093db8", "190c9d8c51ecd8cec465c8db2b78d3b366a8259a",
    "1c224e9c9b64bb344d2ec8c60be27f86d8afed7b", "1cb540439e2f2a7ac980ac9540ebcbb331ae239a",
    "20bd34c7fb06bdc5a093987c7a2c4b4784fba7a2", "216a7fd79aa8cebab5de31897389f00f0a53b00a",
    "27efcfcee5d8ad8684be4d4b625d7239fa97a22a", "290d75235f38757746c445339321e7859907c29a",
    "29556fa7cacb4385313e35768128d890cc31442b", "2ad1822042c03d9a17ed6fbcc60aaf26bd88ace1",
    "2de3eb0631baf11a04430c811413d6b9b652b3d1", "2e6739de30e48a509d6ceb6d0e09fa07f0aee611",
    "2f74f87d6d47cc87bbe5652212fb05b8f5da0036", "2f8abed72bd1172713704d59f4b5bc09ae38e0e9",
    "33d4a1455661e5e56a6172b3881745940955ad70", "340d2a8c98d1a959d65e9e3284af47bb68291f5d",
    "366bad3acd596c4192d62bb09d4e24a3400cb98a", "3ad196afd6a14739dca24bb789545ed4af779123",
    "3c8f8add8d2b02e05475ca04bb69ca7f62510f05", "3fe3469d71682cbbbceed269d292a0aea737d681",
    "40746398164e922d99436a0404a96ef8f04160bd", "40c8a819e5634a574e286f3ad078c4a8fb43d2b4",
    "47caa522ad1e8f82a17e4124ccdf5d542833bfcc", "47fcf562a4a43945f78a8cb8dd4dc5c1d00a64f3",
    "49f7b2740d4e490034e2a85b71ea0aabe8c80489", "4db108ac42e9410c4f606a1b7531abf1e4c382d0",
    "4e60add1565aea33c612ed76439470d3b760302d", "4fa3c4b97679071411d10d636eb301f76d934995",
    "5a41875e39500553a10f93d02bf44cb32c6219b9", "5c1003a6fc60902264155290efe8193ac7777f8c",
    "5e9aaff24de63398a7d41312084b464953d0443c", "615cd55c3745ca431b4907ebdb23272a284b68f4",
    "648c37579df5c834b3f4cb84e2e2127b968188a7", "6bb223c707f99f0311ec2ca4a6761d119f340eee",
    "6c2eae0b5f863bb84637e059dda2d79f4712c4d5", "6d91887e275672aa783fc2e6bd6c14f04cc87d8e",
    "6f8601fcb9ba305bfb19b52fd74e38a9c038c216", "7126a6a910ebd884d15c084e1a30fe987d5b0c46",
    "724207bb18b3bd8b46e15e4fbbea32d622afad90", "75609da55fe2f148151f546948be3bd91c2b8a59",
    "75821f2edb5d65c7b08af735cbe5deafe2aa8d73", "75bca214e8ef1734920c848e303c00350120cc75",
    "7bb2023e9b64a750fe2b1ebfd2e6d27db8f1f3ca", "7c13a10ae21871a02acfa105249ed6b4a739ff1b",
    "7efb164d228a8733ede3bb7e02ceaee2f1facf6e", "83cc14a60c3c64e0d963c3c65b5f3653a747fea4",
    "8528744c4bb41f9ccb98f57769aab862b43675f2", "88ffc35f208a4c3f4964f4f1613368ff4504edc7",
    "9519ea3bd2bddc22a1a99060b5cb46c3906fd726", "97ec9519ee7f486ed3e87f622ae60eddefe09330",
    "a2135390de84633daa93a38831ff67b5765ac69d", "a4372c13b3339a889237aae8026df2ebfa67d7f2",
    "a706ed7a30da7e3b3d75d3bd83092304c73591eb", "a71dab68ea10f06b29ad603d20a0cdcf94abc48e",
    "a7d223f7d195a4c3d5b27fe537dfb5b6c2dbdf39", "aa25ff51e42a2e09a35763805259c6bfebc41705",
    "aa9753c3d01b59d3e91ed1858a9b9dffa14ee5b3", "ae32ac5cbeb0631ef5b4e1eb50cf565767e88376",
    "ae744f21de560831414138697f40f36e94385d90", "ae7ca177c83901ce778f876facef376108096939",
    "ae857789bec3978cc54f20b498d0034334fc2147", "b06d8fc6497ef536127be0693a76670247492274",
    "b207b9c86d185305e682696bf865c9a4501581e4", "b2ff3916274967b1ce2438c5de90e16674be4353",
    "b403e5036b4879e3ddc2ebd33c5984eda0042780", "b5a0f9a73dc242d3671b521ba527be40e60f1841",
    "b6024ffe14633458062a7114cbf9b5a607972021", "b6f24d83fbe87b289ac26f420009ff62d3f94179",
    "b9cfb5c7d6afd6c97d45bd8e641dd635fc53fabd", "be6ea157fb186c11657dcb3cb672b242ff360703",
    "c084ea3d4b145e01ffdf16cfa9ecab21d8ddf3f2", "c54865ee33eca7e752336ab1f177a289500efdae",
    "cbe9ee245c63b85d4b772cc8964a401fd828e313", "ccb879015552da6d70a5308303ae9b65b7e7acc4",
    "d8a33c78309e17f846474596bc73450c1f7f4ab4", "dab6ae8f334eb689f5275b8c706e71c0fad5a707",
    "daeeed993dd14e6063763786e5cc0d4e75706c34", "db6f1405e3df9cf956caec3976680e8d2e35d7cf",
    "de26d360763df7a27ff9a47d883cf5a614754f34", "e6a44f3cb987566c91b59c102dd18efe74b79904",
    "e842e8dea89045bd21e52987a62428106bd2c48c", "e8dcfa6e775cc2c3e4a5483c8b84aa0edb2123a4",
    "e91cccdd70b7c999f2205e75c5e305b0398f9d31", "eb486510a96b12790a7697eb193283f4c0dd0331",
    "f2e3288338ed61f428d78351d2cfc2ce34162a46", "f5aeaa9f8b6bf3b3882511b4121bdfe6078cbfb7",
    "f62a0d3065c7104f68c54020c5766c62e8ea2d4a", "f7ac08bcac429442e35c85a566cd2c1cd1af2a35",
    "f9036da808c14e745a5b168f5bcf42b805309a15", "f94d5cb10e34794ed4b5181d453e7e4fca87e6d7",
    "fd4620d174148afde5469360e0f355db03cae090", "fde61457cb6e05eacae62e0d99eb9046b30f86e4",
};

}  // namespace

std::int64_t rules_of_unmarked_file(std::string_view git) {
  if (git.ends_with("-dirty")) git.remove_suffix(6);
  if (git.size() < 7 || git.size() > 40) return 1;
  const auto match = std::lower_bound(kUnmarkedRules2.begin(), kUnmarkedRules2.end(), git);
  return match != kUnmarkedRules2.end() && match->starts_with(git) ? 2 : 1;
}

std::string rules_words(std::int64_t rules) {
  switch (rules) {
    case 1:
      return "rules 1 (before common random numbers: ggk before 10a1054 of 2026-11-26)";
    case 2:
      return "rules 2 (common random numbers: every fit of a run tests on the run's one "
             "evaluation stream)";
    default:
      return "rules " + std::to_string(rules) + (rules > kResultsRules ? " (a newer ggk's)" : "");
  }
}

std::string rules_mismatch(std::int64_t rules) {
  if (rules == kResultsRules) return {};
  return "its runs were computed under results " + rules_words(rules) +
         " and this ggk computes "
         "under " +
         rules_words(kResultsRules) +
         ": runs of both in one file would equal "
         "neither ggk's results from scratch, so it cannot add runs to it (ggk info, diff and "
         "verify still read it)";
}

}  // namespace ggk::engine
